#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the GoogleTest suite through ctest, then
# again under AddressSanitizer + UndefinedBehaviorSanitizer. The command-line checks (`lacet check
# incremental` on larger scenes) are tests of the Release build's ctest (tests/CMakeLists.txt).
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh

scripts/build.sh build -DCMAKE_BUILD_TYPE=Release -DLACET_BUILD_TESTS=ON -DLACET_MPI=ON
(cd build && ctest --output-on-failure -j 2)

# The sanitized build looks for memory errors and undefined behaviour, not speed: at -O1 with line
# tables only (-g1: stack traces keep their files and lines) it compiles in half the time of -O2 -g.
# The editor's window tests (EditorScript, under xvfb-run) run in the Release build only: under the
# sanitizers they took 228 s of the suite's 612 (2026-12-07). What they run of Lacet's is the editor
# session, which lacet_tests runs sanitized, and the window's own code in ui/, which they alone run.
scripts/build.sh build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" \
  -DLACET_SANITIZE=ON -DLACET_BUILD_BENCH=OFF -DLACET_BUILD_UI_TESTS=OFF
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j 2)
