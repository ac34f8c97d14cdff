// Delaunay tetrahedralization of a TetGen .node point file with the WASM build
// of cdt3d under Node, for tests/bench/bench_delaunay.sh.
//
// usage: node tests/bench/wasm_delaunay.mjs POINTS.node
// Prints one JSON line:
//   {"ok":true,"api":...,"points":N,"tets":T,"msAlgo":a,"msCall":c,"msDelaunay":d,
//    "msParse":p,"msInit":i}
// api is "delaunay" when the package has cdt.delaunay(points) (the call timed),
// else "tetrahedralize": cdt.tetrahedralize({points, triangles: []},
// {stopAfter: 'delaunay'}), which also copies the mesh out and computes quality
// statistics, so there only the module's own msDelaunay is comparable.
// msAlgo is what bench_delaunay.sh compares with native: the module's own
// msDelaunay when it reports one, else msCall. msCall is the wall time of the
// call seen from JS (copying the points into the WASM heap included), msParse
// the JS parsing of the .node text, msInit createCdt3d().
// If the package is not built, prints {"ok":false,"error":"..."} and exits 3.
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';

function fail(message) {
  process.stdout.write(`${JSON.stringify({ ok: false, error: message })}\n`);
  process.exit(3);
}

// Parses a .node file: "N dim attrs markers", then "id x y z [...]" lines;
// '#' starts a comment. Only the coordinates are kept.
function parseNode(text) {
  const lines = text.split('\n');
  let i = 0;
  const next = () => {
    while (i < lines.length) {
      let l = lines[i++];
      const h = l.indexOf('#');
      if (h >= 0) l = l.slice(0, h);
      l = l.trim();
      if (l.length > 0) return l.split(/\s+/);
    }
    return null;
  };
  const head = next();
  if (head === null) throw new Error('empty .node file');
  const n = Number.parseInt(head[0], 10);
  if (!(n >= 0) || Number.parseInt(head[1] ?? '3', 10) !== 3) throw new Error('bad .node header');
  const xyz = new Float64Array(3 * n);
  for (let k = 0; k < n; ++k) {
    const f = next();
    if (f === null || f.length < 4) throw new Error(`.node file ends at point ${k}`);
    xyz[3 * k] = Number(f[1]);
    xyz[3 * k + 1] = Number(f[2]);
    xyz[3 * k + 2] = Number(f[3]);
  }
  return xyz;
}

const file = process.argv[2];
if (!file) {
  process.stderr.write('usage: node tests/bench/wasm_delaunay.mjs POINTS.node\n');
  process.exit(2);
}

let createCdt3d;
try {
  ({ createCdt3d } = await import(new URL('../../wasm/node.js', import.meta.url)));
} catch (e) {
  fail(`cannot load wasm/node.js (is wasm/dist built?): ${e.message}`);
}

const t0 = performance.now();
const points = parseNode(readFileSync(file, 'latin1'));
const msParse = performance.now() - t0;

let cdt;
const t1 = performance.now();
try {
  cdt = await createCdt3d();
} catch (e) {
  fail(`createCdt3d() failed: ${e.message}`);
}
const msInit = performance.now() - t1;
const api = typeof cdt.delaunay === 'function' ? 'delaunay' : 'tetrahedralize';

const t2 = performance.now();
let tets, msDelaunay;
try {
  if (api === 'delaunay') {
    // {tets: number, msDelaunay} or {tets: Uint32Array, stats: {tets, msDelaunay}}.
    const r = cdt.delaunay(points);
    tets = typeof r.tets === 'number' ? r.tets : (r.stats?.tets ?? r.tets.length / 4);
    msDelaunay = r.msDelaunay ?? r.stats?.msDelaunay;
  } else {
    const r = cdt.tetrahedralize(
      { points, triangles: new Uint32Array(0) },
      { stopAfter: 'delaunay', checkIntersections: false },
    );
    tets = r.stats.tets;
    msDelaunay = r.stats.msDelaunay;
  }
} catch (e) {
  fail(`cdt.${api} failed: ${e.code ?? ''} ${e.message}`);
}
const msCall = performance.now() - t2;
const r3 = (x) => (typeof x === 'number' ? Number(x.toFixed(3)) : null);

process.stdout.write(
  `${JSON.stringify({
    ok: true,
    api,
    points: points.length / 3,
    tets: typeof tets === 'number' ? tets : null,
    msAlgo: r3(typeof msDelaunay === 'number' ? msDelaunay : msCall),
    msCall: r3(msCall),
    msDelaunay: r3(msDelaunay),
    msParse: r3(msParse),
    msInit: r3(msInit),
  })}\n`,
);
