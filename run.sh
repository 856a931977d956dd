#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on a sample scene, headless (the editor
# window comes with its issue): with the Andorra data beside the repository, imports it into
# build/andorra.gpkg, prints its summary and renders it; otherwise a synthetic scene at a tenth of
# the paper's size, its view-refined quadtree, a summary and renders of its appearance.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -DLACET_BUILD_TESTS=OFF
andorra=../shared/data/andorra
if [ -f "$andorra/andorra-2021-04-14.osm.pbf" ] && [ -f "$andorra/N42E001.hgt.zip" ]; then
  # The real scene: Andorra (© OpenStreetMap contributors, ODbL; SRTM), imported, then rendered.
  samples/andorra/import.sh build/andorra.gpkg
  ./build/lacet info build/andorra.gpkg --json
  ./build/lacet render --scene build/andorra.gpkg --level 3 --layer appearance --out build/run-overview.png
  ./build/lacet render --scene build/andorra.gpkg --level 3 --layer elevation --out build/run-elevation.png
else
  ./build/lacet synth --seed 1 --curves 60000 --view-altitude 10 "$@"
  ./build/lacet render --seed 1 --curves 60000 --level 3 --layer appearance --out build/run-overview.png
  ./build/lacet render --seed 1 --curves 60000 --level 10 --region 15700,15700,15900,15900 --layer appearance --out build/run-closeup.png
fi
