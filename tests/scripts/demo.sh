#!/usr/bin/env bash
# The main job (`npm start`): build everything, mesh a sample model, then
# serve the browser demo (web/) and print its URL.
#   npm start                      bunny.off, then the demo page
#   npm start -- path/to/model.stl another model
# Without a terminal (CI, pipes) or with CDT3D_NO_SERVE=1 the page is only
# built (web/dist), not served. PORT picks the port (default 5173, or the
# next free one).
set -euo pipefail
cd "$(dirname "$0")/../.."
bash tests/scripts/setup.sh
bash tests/scripts/build.sh
model=${1:-tests/data/bunny.off}
echo "== native:"
.build/native/core/cdt3d info "$model"
echo "== WASM (Node):"
node --input-type=module -e '
import { readFileSync } from "node:fs";
import { basename } from "node:path";
import { createCdt3d } from "cdt3d";
const file = process.argv[1];
const cdt = await createCdt3d();
const bytes = readFileSync(file);
console.log(cdt.readPlc(bytes, file));
if (typeof cdt.tetrahedralize === "function") {
  try {
    const { stats, validation } = cdt.tetrahedralize({ bytes, fileName: basename(file) }, { validate: true });
    const keep = Object.fromEntries(Object.entries(stats).filter(([, v]) => typeof v !== "object"));
    console.log({ ...keep, validation: validation && validation.ok ? "ok" : validation ? validation.message : "not run" });
  } catch (e) {
    console.log(`${file}: ${e.code}: ${e.message}`);
  }
}' "$model"

echo "== web demo:"
./node_modules/.bin/vite build web --logLevel warn
echo "built web/dist (a static site: any web server can serve it)"
if [ -t 1 ] && [ -z "${CI:-}" ] && [ "${CDT3D_NO_SERVE:-0}" != 1 ]; then
  port=$(node -e '
const net = require("node:net");
const tryPort = (p) => {
  const s = net.createServer();
  s.once("error", () => tryPort(p === 0 ? 0 : p + 1 > 65535 ? 0 : p + 1));
  s.listen(p, "127.0.0.1", () => { const got = s.address().port; s.close(() => console.log(got)); });
};
tryPort(Number(process.argv[1]));' "${PORT:-5173}")
  echo
  echo "  cdt3d demo: http://127.0.0.1:${port}/   (Ctrl+C stops)"
  echo
  exec ./node_modules/.bin/vite preview web --host 127.0.0.1 --port "$port" --strictPort
else
  echo "not serving (no terminal); to see the page: npx vite preview web"
fi
