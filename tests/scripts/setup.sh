#!/usr/bin/env bash
# Installs what cdt3d's build and tests need on a fresh Debian 12 machine.
# Idempotent and unattended: skips what is already there.
set -euo pipefail
cd "$(dirname "$0")/../.."

need=()
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
# gmsh, python3-meshio and python3-vtk9 read the Gmsh and VTU output back
# in the tests (tests/formats/check_formats.py).
for pkg in cmake g++ make catch2 libgmp-dev emscripten time chromium clang-14 libclang-rt-14-dev llvm-14 \
    gmsh python3-meshio python3-vtk9 ${CDT3D_EXTRA_APT:-}; do
  have_pkg "$pkg" || need+=("$pkg")
done
if [ ${#need[@]} -gt 0 ]; then
  echo "setup: installing ${need[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

# npm ci when node_modules is missing or older than the lock file.
if [ ! -d node_modules ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  echo "setup: npm ci"
  npm ci --no-audit --no-fund --loglevel=error
fi
