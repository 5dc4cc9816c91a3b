#!/usr/bin/env bash
# First command of the README: install what is missing, build, run the Rock Pile demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
mkdir -p out
build/rbpart simulate --scene rock_pile --steps 500 --stats out/rock_pile.csv --state out/rock_pile_state.json
