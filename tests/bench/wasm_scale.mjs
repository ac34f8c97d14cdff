// One model through the npm package under Node, for tests/bench/bench_scale.sh.
//
// usage: node tests/bench/wasm_scale.mjs MODEL [--read]
// Prints one JSON line: {"ok":true,"points":N,"tets":T,"msRead":..,"msDelaunay":..,
// "msSegments":..,"msFacets":..,"msCarve":..,"msTotal":..,"msCall":c} with the
// module's own phase clocks (the same as the native CLI's --json), or
// {"ok":false,"code":"...","error":"..."} when the package refuses or fails
// (exit 1; 3 when the package is not built). One call in a fresh process:
// the bench reads the peak memory of the whole process.
//
// With --read it only reads: readPlc() twice, the first call in a fresh
// WebAssembly instance (its heap pages untouched, its code not yet
// optimised by the engine) and the second in a used one; it prints
// {"ok":true,"msFirst":..,"msSecond":..,"facets":N}, each call alone (the
// file is read from disk before).
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { performance } from 'node:perf_hooks';

const out = (o) => process.stdout.write(`${JSON.stringify(o)}\n`);
const file = process.argv[2];
if (!file) {
  process.stderr.write('usage: node tests/bench/wasm_scale.mjs MODEL [--read]\n');
  process.exit(2);
}
let createCdt3d;
try {
  ({ createCdt3d } = await import(new URL('../../wasm/node.js', import.meta.url)));
} catch (e) {
  out({ ok: false, code: 'not-built', error: `cannot load wasm/node.js: ${e.message}` });
  process.exit(3);
}
const cdt = await createCdt3d();
const bytes = readFileSync(file);
if (process.argv[3] === '--read') {
  const ms = [];
  let facets = 0;
  try {
    for (let k = 0; k < 2; k++) {
      const t = performance.now();
      facets = cdt.readPlc(bytes, path.basename(file)).facets;
      ms.push(performance.now() - t);
    }
  } catch (e) {
    out({ ok: false, code: e.code ?? 'error', error: e.message });
    process.exit(1);
  }
  out({ ok: true, msFirst: Math.round(ms[0]), msSecond: Math.round(ms[1]), facets });
  process.exit(0);
}
const t0 = performance.now();
let r;
try {
  r = cdt.tetrahedralize({ bytes, fileName: path.basename(file) });
} catch (e) {
  out({ ok: false, code: e.code ?? 'error', error: e.message });
  process.exit(1);
}
const msCall = performance.now() - t0;
const s = r.stats;
const r3 = (x) => (typeof x === 'number' ? Number(x.toFixed(3)) : null);
const o = { ok: true, points: s.points, tets: s.tets };
for (const k of ['msRead', 'msDelaunay', 'msSegments', 'msDegeneracy', 'msFacets', 'msCarve', 'msTotal'])
  o[k] = r3(s[k]);
o.msCall = r3(msCall);
out(o);
