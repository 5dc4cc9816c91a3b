#!/usr/bin/env bash
# Second command of the README: install what is missing, build, run the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
# AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer on the stages that read input,
# partition and refine, and on the fuzz corpus (tests/corpus) through the CLI, every solver included;
# a validate build, so partitions, refiners' gains and solves with kept factors are re-checked from
# scratch as they run. (The solve tests would add about 5 minutes here: 3 to build, 2 to run.)
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DRBPART_SANITIZE=ON -DRBPART_VALIDATE=ON \
  -DRBPART_BUILD_PYTHON=OFF -DRBPART_BUILD_VIEWER=OFF -DRBPART_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j "$(nproc)" --target rbpart rbpart_io_tests rbpart_graph_tests rbpart_partition_tests \
  rbpart_refine_tests rbpart_scene_tests rbpart_corpus_tests
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir build-asan --output-on-failure \
  -j "$(nproc)" -L '^(io|graph|partition|refine|scene|corpus)$'
# The library as its users get it (README, "Embedding: C++ and Python"): installed into a temporary
# prefix, the example program built against that installed CMake package and run, and the Python
# module's tests run on the installed module.
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install build --prefix "$prefix/usr" >/dev/null
cmake -S examples -B "$prefix/examples" -DCMAKE_PREFIX_PATH="$prefix/usr" >/dev/null
cmake --build "$prefix/examples" -j "$(nproc)"
"$prefix/examples/drop_boxes"
python_dir="$(sed -n 's/^RBPART_PYTHON_INSTALL_DIR:STRING=//p' build/CMakeCache.txt)"
PYTHONPATH="$prefix/usr/$python_dir" /usr/bin/python3 -m pytest -q -p no:cacheprovider python/tests
# The optional peers' comparison (bench/peers/), only where scripts/install_peers.sh has installed them.
if dpkg-query -W -f='${Status}\n' libode-dev libmujoco-dev libbullet-extras-dev 2>/dev/null | grep -c "install ok installed" | grep -qx 3; then
  bench/peers/smoke.sh
fi
