#!/usr/bin/env bash
# The main job: build everything, then print the summary of a bundled sample.
set -euo pipefail
cd "$(dirname "$0")/../.."
bash tests/scripts/setup.sh
bash tests/scripts/build.sh
model=${1:-tests/data/bunny.off}
echo "== native:"
build/core/cdt3d info "$model"
echo "== WASM (Node):"
node -e '
import("cdt3d").then(async ({ createCdt3d }) => {
  const fs = await import("node:fs");
  const cdt = await createCdt3d();
  const file = process.argv[1];
  console.log(cdt.readPlc(fs.readFileSync(file), file));
});' "$model"
