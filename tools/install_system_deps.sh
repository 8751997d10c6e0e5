#!/usr/bin/env bash
# Install the Debian packages hitogata needs, only those that are missing.
#   render: Mesa's EGL/OpenGL for pyvista's offscreen pictures (no display, no GPU)
#   test:   the above, plus Node.js/npm (Khronos glTF validator) and Chromium (viewer browser test)
set -euo pipefail
missing=()
for pkg in libegl1 libegl-mesa0 libgl1-mesa-dri; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if [ "${1:-render}" = "test" ]; then
  command -v node >/dev/null && command -v npm >/dev/null || missing+=(nodejs npm)
  command -v chromium >/dev/null || missing+=(chromium)
fi
[ ${#missing[@]} -eq 0 ] && exit 0
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "installing system packages: ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
