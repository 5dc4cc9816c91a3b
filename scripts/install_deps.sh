#!/usr/bin/env bash
# Installs the Debian 12 packages rbpart builds on, only those that are missing.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libbullet-dev libtbb-dev libsuitesparse-dev libmetis-dev
  libcli11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
  zlib1g-dev libcpp-httplib-dev  # recordings (gzip), `rbpart view`'s server
  chromium                       # `rbpart snapshot` and the viewer's end-to-end test
  python3-matplotlib             # `rbpart bench`'s figures (scripts/plot_study.py, system Python)
  pybind11-dev python3-numpy     # the Python module (python/), for the system Python
  python3-pytest                 # its tests (python/tests)
)
# The viewer's build (scripts/build_viewer.sh) needs node and npm; Debian's own (node 18, npm 9) do,
# and a node that is already there (with its bundled npm) is kept.
command -v node >/dev/null && command -v npm >/dev/null || packages+=(nodejs npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}" >&2
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
