#!/bin/sh
# Installs what bench/render/render.mjs needs, when missing: Chromium (Debian/Ubuntu apt, as root)
# and three (npm ci from package-lock.json). Safe to run again.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
if ! command -v chromium >/dev/null 2>&1; then
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends chromium
fi
if [ ! -f "$here/node_modules/three/build/three.module.js" ]; then
    (cd "$here" && npm ci --no-audit --no-fund)
fi
chromium --version
echo "three $(node -p "require('$here/node_modules/three/package.json').version")"
