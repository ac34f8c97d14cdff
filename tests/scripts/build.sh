#!/usr/bin/env bash
# Builds the native tree (library, CLI, tests) and the WASM package.
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=$(nproc 2>/dev/null || echo 2)

cmake -S . -B .build/native -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build .build/native -j"$JOBS"

# Debian's emscripten needs Node to find its acorn module (TOOLCHAIN.md).
export NODE_PATH=/usr/share/nodejs
if [ ! -f .build/wasm/CMakeCache.txt ]; then
  emcmake cmake -S . -B .build/wasm -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build .build/wasm -j"$JOBS"
