// A small model the worker meshes before the first real one (cdt3d/worker's
// prepare()): WebAssembly engines compile each function cheaply first and
// optimise the ones that run often, so a module's first large call runs
// several times slower than later ones. Meshing this model a few times
// makes the pipeline's hot functions (parsers, predicates, every step and
// the validator) hot before a user's model arrives.
//
// A closed, star-shaped bumpy sphere with a flat base: its long thin
// triangles need Steiner points on segments, the base is a merged flat
// facet. Rounds 0-2 mesh 5k triangles written as OFF, OBJ and binary STL,
// so that each common reader runs; round 3 meshes 48k triangles (24k
// points, its radius made rough like a scan's, which leaves facet
// recovery thousands of cavities), for the code that only large inputs
// reach (step 1's rounds on the second thread from 20,000 points) and a
// heap grown to their size: without it a first model of 100k+ triangles
// still ran about twice as slow as later ones. Later rounds repeat the
// small ones.

const FORMATS = ['off', 'obj', 'stl'];
const LARGE_ROUND = 3;

// Points and triangles of the surface: `rings` latitude rings of `sectors`
// points between two poles, outward-facing (counterclockwise seen from
// outside). Radius bumps keep the surface a graph over the sphere's
// directions, so it cannot intersect itself.
function bumpySphere(rings, sectors, roughness = 0) {
  const points = [];
  let seed = 12345;
  // Deterministic noise in [0, 1) (an LCG): the radius of a scan is rough.
  const noise = () => {
    seed = (Math.imul(seed, 1103515245) + 12345) >>> 0;
    return seed / 2 ** 32;
  };
  const push = (theta, phi) => {
    const r =
      1 + 0.08 * Math.sin(5 * theta) * Math.sin(4 * phi) + 0.05 * Math.cos(7 * phi) + roughness * (noise() - 0.5);
    const x = r * Math.sin(phi) * Math.cos(theta);
    const y = r * Math.sin(phi) * Math.sin(theta);
    // The bottom cut flat: one plane, many coplanar triangles.
    const z = Math.max(r * Math.cos(phi), -0.7);
    points.push(x, y, z);
  };
  push(0, 0);
  for (let i = 1; i <= rings; i++) {
    const phi = (Math.PI * i) / (rings + 1);
    for (let j = 0; j < sectors; j++) push((2 * Math.PI * j) / sectors + (i % 2) * (Math.PI / sectors), phi);
  }
  push(0, Math.PI);
  const south = rings * sectors + 1;
  const at = (i, j) => 1 + (i - 1) * sectors + (j % sectors);
  const triangles = [];
  for (let j = 0; j < sectors; j++) triangles.push(0, at(1, j), at(1, j + 1));
  for (let i = 1; i < rings; i++) {
    for (let j = 0; j < sectors; j++) {
      triangles.push(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      triangles.push(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  for (let j = 0; j < sectors; j++) triangles.push(south, at(rings, j + 1), at(rings, j));
  return { points, triangles };
}

function toOff({ points, triangles }) {
  const lines = ['OFF', `${points.length / 3} ${triangles.length / 3} 0`];
  for (let i = 0; i < points.length; i += 3) lines.push(`${points[i]} ${points[i + 1]} ${points[i + 2]}`);
  for (let i = 0; i < triangles.length; i += 3) lines.push(`3 ${triangles[i]} ${triangles[i + 1]} ${triangles[i + 2]}`);
  return new TextEncoder().encode(lines.join('\n') + '\n');
}

function toObj({ points, triangles }) {
  const lines = [];
  for (let i = 0; i < points.length; i += 3) lines.push(`v ${points[i]} ${points[i + 1]} ${points[i + 2]}`);
  for (let i = 0; i < triangles.length; i += 3) {
    lines.push(`f ${triangles[i] + 1} ${triangles[i + 1] + 1} ${triangles[i + 2] + 1}`);
  }
  return new TextEncoder().encode(lines.join('\n') + '\n');
}

function toStl({ points, triangles }) {
  const n = triangles.length / 3;
  const out = new DataView(new ArrayBuffer(84 + 50 * n));
  out.setUint32(80, n, true);
  for (let t = 0; t < n; t++) {
    const o = 84 + 50 * t + 12; // the normal (left zero) first
    for (let k = 0; k < 3; k++) {
      const v = triangles[3 * t + k];
      for (let a = 0; a < 3; a++) out.setFloat32(o + 12 * k + 4 * a, points[3 * v + a], true);
    }
  }
  return new Uint8Array(out.buffer);
}

/** The warm-up model of round `round` (>= 0) as a file: {bytes, fileName}. */
export function warmUpModel(round) {
  const large = round === LARGE_ROUND;
  const format = large ? 'obj' : FORMATS[round % FORMATS.length];
  const surface = large ? bumpySphere(120, 200, 0.01) : bumpySphere(40, 64);
  const bytes = format === 'off' ? toOff(surface) : format === 'obj' ? toObj(surface) : toStl(surface);
  return { bytes, fileName: `warm-up.${format}` };
}
