#!/usr/bin/env bash
# Second command of the README: install what is missing, build, run the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
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
