#!/usr/bin/env bash
# Fuzzes the GeoJSON reader and the scene-file reader with libFuzzer under ASan + UBSan, each for
# a bounded time: scripts/fuzz.sh [SECONDS per target, default 60]. Builds build-fuzz/ with clang.
# Seeds: the GeoJSON corpus in tests/data/vectors and a small synthetic scene file.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
scripts/install_deps.sh
if ! command -v clang++ >/dev/null; then
  apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev
fi
CC=clang CXX=clang++ scripts/build.sh build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLACET_FUZZ=ON \
  -DLACET_BUILD_TESTS=OFF -DLACET_BUILD_BENCH=OFF -DLACET_DEVELOPER_BUILD=OFF
mkdir -p build-fuzz/corpus/geojson build-fuzz/corpus/scene
cp tests/data/vectors/*.geojson build-fuzz/corpus/geojson/
if [ ! -f build-fuzz/corpus/scene/seed.gpkg ]; then
  scripts/build.sh build -DCMAKE_BUILD_TYPE=Release >/dev/null
  ./build/lacet synth --curves 200 --dem-resolution 2000 --out build-fuzz/corpus/scene/seed.gpkg >/dev/null
fi
export ASAN_OPTIONS=detect_leaks=0  # GDAL keeps driver registries alive until exit
./build-fuzz/fuzz/geojson_fuzz -max_total_time="$seconds" -max_len=65536 -timeout=10 build-fuzz/corpus/geojson
./build-fuzz/fuzz/scene_file_fuzz -max_total_time="$seconds" -max_len=1000000 -timeout=10 build-fuzz/corpus/scene
echo "fuzz: no crash and no sanitizer report in ${seconds} s per target"
