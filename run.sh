#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on a sample scene: the Andorra scene when
# its data is beside the repository (imported into build/andorra.gpkg), otherwise a synthetic
# one. With a display, the editor opens on it; without one, the scene's summary is printed, it is
# rendered to PNGs, and the editor draws a view of it headless (xvfb-run, Mesa's software OpenGL)
# to build/editor-view/ and prints the view's figures.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -DLACET_BUILD_TESTS=OFF
andorra=../shared/data/andorra
scene=()
if [ -f "$andorra/andorra-2021-04-14.osm.pbf" ] && [ -f "$andorra/N42E001.hgt.zip" ]; then
  # The real scene: Andorra (© OpenStreetMap contributors, ODbL; SRTM).
  [ -f build/andorra.gpkg ] || samples/andorra/import.sh build/andorra.gpkg
  scene=(build/andorra.gpkg)
fi
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec ./build/lacet edit "${scene[@]}" "$@"
fi
if [ ${#scene[@]} -gt 0 ]; then
  ./build/lacet info build/andorra.gpkg --json
  ./build/lacet render --scene build/andorra.gpkg --level 3 --layer appearance --out build/run-overview.png
  ./build/lacet render --scene build/andorra.gpkg --level 3 --layer elevation --out build/run-elevation.png
else
  ./build/lacet synth --seed 1 --curves 60000 --view-altitude 10
  ./build/lacet render --seed 1 --curves 60000 --level 3 --layer appearance --out build/run-overview.png
fi
xvfb-run -a -s "-screen 0 1280x800x24" ./build/lacet edit "${scene[@]}" --script samples/editor/view.json --out build/editor-view
echo "Headless view of the editor: build/editor-view/view.png, build/editor-view/closeup.png"
