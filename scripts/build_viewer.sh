#!/usr/bin/env bash
# Builds the web viewer (viewer/) into static files, build/viewer/{index.html,viewer.js,viewer.css}
# or the directory given as $1; `rbpart view` and `rbpart snapshot` serve them (docs/viewer.md).
# `npm ci` installs the locked three.js and esbuild from the npm registry into viewer/node_modules
# when the lock file is newer than the installed tree; the build itself runs offline.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-build/viewer}"
if [ ! -f viewer/node_modules/.package-lock.json ] || [ viewer/package-lock.json -nt viewer/node_modules/.package-lock.json ]; then
  (cd viewer && npm ci --no-audit --no-fund --loglevel=error)
fi
node viewer/build.mjs "$out"
