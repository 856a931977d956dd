#!/usr/bin/env bash
# Builds the Andorra scene from the OSM extract and SRTM tile in ../shared/data/andorra/ (read in
# place, never copied into the repository): samples/andorra/import.sh [OUT.gpkg] [lacet import options]
# Data © OpenStreetMap contributors (ODbL 1.0); SRTM: NASA/USGS, public domain.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${LACET_ANDORRA_DATA:-$root/../shared/data/andorra}
out=${1:-$root/build/andorra.gpkg}
shift || true
"$root/build/lacet" import \
  --dem "/vsizip/$data/N42E001.hgt.zip/N42E001.hgt" \
  --vectors "$data/andorra-2021-04-14.osm.pbf" \
  --out "$out" "$@"
