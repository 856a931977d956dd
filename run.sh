#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on a sample scene: a synthetic scene at
# a tenth of the paper's size, its quadtree refined for a viewer near the ground, and a summary;
# then a headless render of its appearance: the whole scene, and a close-up of its centre.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -DLACET_BUILD_TESTS=OFF
./build/lacet synth --seed 1 --curves 60000 --view-altitude 10 "$@"
./build/lacet render --seed 1 --curves 60000 --level 3 --layer appearance --out build/run-overview.png
./build/lacet render --seed 1 --curves 60000 --level 10 --region 15700,15700,15900,15900 --layer appearance --out build/run-closeup.png
