#!/usr/bin/env bash
# Fuzzes Lacet's readers with libFuzzer under ASan + UBSan, each target for a bounded time:
#   scripts/fuzz.sh [SECONDS per target, default 60] [TARGET ...]
# Targets (fuzz/): geojson_fuzz, osm_xml_fuzz, osm_pbf_fuzz, mapping_fuzz, dem_fuzz,
# scene_file_fuzz, pyramid_fuzz (default: all). Builds build-fuzz/ with clang. Seed corpora are made
# here from real files, in build-fuzz/corpus/TARGET (kept between runs, never in the repository):
# the GeoJSON and OSM test inputs, the Andorra OSM extract and cuts of its SRTM tile (../shared/data,
# read in place), the default mapping, a small synthetic scene and its pyramid. A target's findings
# are written as crash-*/leak-*/timeout-* files in build-fuzz/findings/TARGET; each becomes a
# regression test with its input. Prints the executions and coverage of each target.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(geojson_fuzz osm_xml_fuzz osm_pbf_fuzz mapping_fuzz dem_fuzz scene_file_fuzz pyramid_fuzz)
andorra=${LACET_ANDORRA_DATA:-$(pwd)/../shared/data/andorra}

scripts/install_deps.sh
if ! command -v clang++ >/dev/null; then
  apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev
fi
CC=clang CXX=clang++ scripts/build.sh build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLACET_FUZZ=ON \
  -DLACET_BUILD_TESTS=OFF -DLACET_BUILD_BENCH=OFF -DLACET_DEVELOPER_BUILD=OFF

corpus=build-fuzz/corpus
mkdir -p "$corpus"/{geojson_fuzz,osm_xml_fuzz,osm_pbf_fuzz,mapping_fuzz,dem_fuzz,scene_file_fuzz,pyramid_fuzz}
cp tests/data/vectors/*.geojson "$corpus/geojson_fuzz/"
cp tests/data/vectors/*.osm "$corpus/osm_xml_fuzz/"
cp tests/data/vectors/*.json "$corpus/mapping_fuzz/"
[ -f "$andorra/andorra-2021-04-14.osm.pbf" ] && cp "$andorra/andorra-2021-04-14.osm.pbf" "$corpus/osm_pbf_fuzz/andorra.osm.pbf"
if [ ! -f "$corpus/scene_file_fuzz/seed.gpkg" ] || [ ! -f "$corpus/pyramid_fuzz/seed.pyramid.gpkg" ] ||
   [ ! -f "$corpus/mapping_fuzz/default.json" ] || [ ! -f "$corpus/dem_fuzz/srtm_cut.tif" ]; then
  scripts/build.sh build -DCMAKE_BUILD_TYPE=Release >/dev/null
  ./build/lacet synth --curves 200 --dem-resolution 2000 --out "$corpus/scene_file_fuzz/seed.gpkg" >/dev/null
  ./build/lacet pyramid build "$corpus/scene_file_fuzz/seed.gpkg" --levels 0-2 --out "$corpus/pyramid_fuzz/seed.pyramid.gpkg" >/dev/null
  # The default mapping, as io/feature_mapping.cpp holds it.
  awk '/kDefaultMapping = R"json\(/{on=1; sub(/.*R"json\(/, ""); print; next} on && /\)json";/{sub(/\)json";.*/, ""); print; on=0} on' io/feature_mapping.cpp \
    > "$corpus/mapping_fuzz/default.json"
  if [ -f "$andorra/N42E001.hgt.zip" ]; then
    gdal_translate -q -of GTiff -srcwin 500 500 24 24 "/vsizip/$andorra/N42E001.hgt.zip/N42E001.hgt" "$corpus/dem_fuzz/srtm_cut.tif"
    gdal_translate -q -of GTiff -co COMPRESS=DEFLATE -co PREDICTOR=2 -srcwin 600 600 16 16 \
      "/vsizip/$andorra/N42E001.hgt.zip/N42E001.hgt" "$corpus/dem_fuzz/srtm_deflate.tif"
  fi
fi

export ASAN_OPTIONS=detect_leaks=0  # GDAL keeps driver registries alive until exit
failed=0
for t in "${targets[@]}"; do
  findings=build-fuzz/findings/$t
  mkdir -p "$findings"
  args=(-max_total_time="$seconds" -timeout=10 -print_final_stats=1 -artifact_prefix="$findings/")
  case $t in
    osm_xml_fuzz) args+=(-max_len=65536 -dict=fuzz/osm_xml.dict) ;;
    osm_pbf_fuzz) args+=(-max_len=2000000) ;;
    scene_file_fuzz | pyramid_fuzz | dem_fuzz) args+=(-max_len=1000000) ;;
    *) args+=(-max_len=65536) ;;
  esac
  echo "== $t (${seconds} s)"
  if ! "./build-fuzz/fuzz/$t" "${args[@]}" "$corpus/$t" 2> "build-fuzz/$t.log"; then
    failed=1
    echo "$t: a finding, in $findings (log: build-fuzz/$t.log)"
  fi
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|cov: [0-9]+" "build-fuzz/$t.log" | grep -E "stat::|DONE" | tr '\n' ' '
  grep -Eo "cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9]+[a-zA-Z]+" "build-fuzz/$t.log" | tail -1
done
[ $failed -eq 0 ] && echo "fuzz: no crash and no sanitizer report in ${seconds} s per target"
exit $failed
