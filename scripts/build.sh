#!/usr/bin/env bash
# Configures and builds rbpart in Release mode into build/ (the CLI lands at build/rbpart), and the
# web viewer into build/viewer/.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
scripts/build_viewer.sh build/viewer
