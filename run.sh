#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on a sample scene: a synthetic scene at
# a tenth of the paper's size, its quadtree refined for a viewer near the ground, and a summary.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -DLACET_BUILD_TESTS=OFF
./build/lacet synth --seed 1 --curves 60000 --view-altitude 10 "$@"
