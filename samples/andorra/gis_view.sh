#!/usr/bin/env bash
# Draws a scene file's vector layers over its DEM with GDAL's command-line tools only, the way any
# GIS tool reads the file: a hillshade of the `dem` raster, then each feature table (written by
# saveScene, io/scene_features.h) burnt in the colour of its layer kind, roads last.
#   samples/andorra/gis_view.sh SCENE.gpkg OUT.png [WIDTH]
# WIDTH (pixels, default 1600) is the image's width; lines are one pixel wide at any width.
# For the Andorra scene: © OpenStreetMap contributors (ODbL); SRTM: NASA/USGS.
set -euo pipefail
if [[ $# -lt 2 || $# -gt 3 ]]; then
  echo "usage: $0 SCENE.gpkg OUT.png [WIDTH]" >&2
  exit 2
fi
scene=$1
out=$2
width=${3:-1600}
for tool in gdaldem gdal_translate gdal_rasterize ogr2ogr; do
  command -v "$tool" >/dev/null || { echo "$0: $tool not found (Debian: apt-get install gdal-bin)" >&2; exit 1; }
done
[[ -f $scene ]] || { echo "$0: no such file: $scene" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The hillshade (heights and cells in metres), lightened so the layers' colours stand out, as RGB.
gdaldem hillshade -q -multidirectional -compute_edges "GPKG:$scene:dem" "$tmp/hillshade.tif" ||
  { echo "$0: $scene has no readable 'dem' raster to draw over" >&2; exit 1; }
gdal_translate -q -outsize "$width" 0 -r bilinear -scale 0 255 110 255 -ot Byte \
  -b 1 -b 1 -b 1 -co PHOTOMETRIC=RGB "$tmp/hillshade.tif" "$tmp/view.tif"

# The feature tables of one layer kind: gpkg_contents.description starts with "Lacet <kind> layer".
tables_of() {
  ogr2ogr -q -f CSV /vsistdout/ "$scene" -sql \
    "SELECT table_name FROM gpkg_contents WHERE data_type = 'features' AND description LIKE 'Lacet $1 layer%' ORDER BY table_name" |
    tail -n +2 | tr -d '"\r'
}

# Areas first, then rivers over them, roads on top.
declare -A colour=([fields]="225 200 70" [forests]="40 125 50" [other]="150 150 150" [lakes]="70 150 235"
                   [rivers]="20 80 220" [roads]="205 25 25")
drawn=0
for kind in fields forests other lakes rivers roads; do
  read -r r g b <<<"${colour[$kind]}"
  while read -r table; do
    [[ -n $table ]] || continue
    gdal_rasterize -q -l "$table" -b 1 -b 2 -b 3 -burn "$r" -burn "$g" -burn "$b" "$scene" "$tmp/view.tif"
    drawn=$((drawn + 1))
  done < <(tables_of "$kind")
done
[[ $drawn -gt 0 ]] || echo "$0: warning: $scene holds no Lacet feature tables (saved by an older Lacet?)" >&2

# No .aux.xml beside the PNG: the picture carries no georeference.
gdal_translate -q -of PNG --config GDAL_PAM_ENABLED NO "$tmp/view.tif" "$out"
echo "$out: $drawn feature tables over the DEM of $scene"
