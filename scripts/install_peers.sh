#!/usr/bin/env bash
# Installs the Debian 12 packages of the optional peers' comparison (bench/peers/README.md): ODE
# 0.16, Bullet 3.24 with its extras, MuJoCo 2.2. Neither rbpart's build nor its test suite needs
# them, and scripts/install_deps.sh does not install them; scripts/test.sh runs the comparison's
# smoke test only where all of them are installed.
set -euo pipefail
peers=(libode-dev libbullet-dev libbullet-extras-dev libmujoco-dev nlohmann-json3-dev cmake pkg-config python3-matplotlib)
installed=$(dpkg-query -W -f='${Status}\n' "${peers[@]}" 2>/dev/null | grep -c "install ok installed" || true)
if [ "$installed" -lt ${#peers[@]} ]; then
  as_root=()
  [ "$(id -u)" -eq 0 ] || as_root=(sudo)
  "${as_root[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${as_root[@]}" apt-get install -y -qq --no-install-recommends "${peers[@]}" >/dev/null
fi
