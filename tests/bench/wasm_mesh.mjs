// The whole CDT pipeline on one model file with the WASM build of cdt3d under
// Node, for tests/bench/bench_corpus.sh (the WASM / native ratio per model).
//
// usage: node tests/bench/wasm_mesh.mjs MODEL
// Prints one JSON line:
//   {"ok":true,"points":N,"tets":T,"steiner":S,"msTotal":t,"msDelaunay":d,"msCall":c,
//    "msTotalWarm":w}
// msTotal and msDelaunay are the module's own phase clocks (the same clocks
// as the native CLI's --json msTotal / msDelaunay, so the two compare the
// mesher and not Node's start-up); msCall is the wall time of the call seen
// from JS (copying in and out of the WASM heap included). All three are the
// first call in a fresh process: V8 compiles each function on its first
// call and runs most of that call in its baseline compiler (Liftoff), so
// they include the JIT's warm-up. msTotalWarm is the fastest msTotal of
// more calls on the same model in the same process, at least WARM (default
// 4) and for at least WARM_MS (default 1500) ms, at most 100: V8 moves a
// function to its optimizing compiler (TurboFan) once it has run for a
// while, which a model of a few ms reaches only after many calls. That is
// the steady state of an app that meshes more than once, and the compiled
// code's speed against native code.
// Errors print {"ok":false,"error":"..."}: exit 3 when the package is not
// built, 1 when meshing fails.
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { performance } from 'node:perf_hooks';

function fail(message, code) {
  process.stdout.write(`${JSON.stringify({ ok: false, error: message })}\n`);
  process.exit(code);
}

const file = process.argv[2];
if (!file) {
  process.stderr.write('usage: node tests/bench/wasm_mesh.mjs MODEL\n');
  process.exit(2);
}

let createCdt3d;
try {
  ({ createCdt3d } = await import(new URL('../../wasm/node.js', import.meta.url)));
} catch (e) {
  fail(`cannot load wasm/node.js (is wasm/dist built?): ${e.message}`, 3);
}
const cdt = await createCdt3d();
const bytes = readFileSync(file);

const t0 = performance.now();
let r;
try {
  r = cdt.tetrahedralize({ bytes, fileName: path.basename(file) });
} catch (e) {
  fail(`${e.code ?? 'error'}: ${e.message}`, 1);
}
const msCall = performance.now() - t0;
let msTotalWarm = Infinity;
const warm = Number(process.env.WARM ?? 4);
const warmMs = Number(process.env.WARM_MS ?? 1500);
const tWarm = performance.now();
for (let i = 0; i < 100 && (i < warm || performance.now() - tWarm < warmMs); i++) {
  const again = cdt.tetrahedralize({ bytes, fileName: path.basename(file) });
  msTotalWarm = Math.min(msTotalWarm, again.stats.msTotal);
}
const r3 = (x) => Number(x.toFixed(3));
const s = r.stats;
process.stdout.write(
  `${JSON.stringify({
    ok: true,
    points: s.points,
    tets: s.tets,
    steiner: s.steinerSegment + s.steinerFacet + s.steinerVolume,
    msTotal: r3(s.msTotal),
    msDelaunay: r3(s.msDelaunay),
    msCall: r3(msCall),
    msTotalWarm: warm > 0 ? r3(msTotalWarm) : null,
  })}\n`,
);
