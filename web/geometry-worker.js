// Turns a cdt3d result into GPU-ready arrays off the main thread, so that a
// mesh of 500k tetrahedra never blocks the page.
//
// Requests:
//   {type: 'build', id, points, tets, faces, tetAttributes, inputPoints, steinerKinds, origin, axis, flip}
//     -> {type: 'built', id, position, center, flags, quality, region, regionValues,
//         histogram, steinerPosition, steinerKinds, order: {...}}
//   {type: 'order', id, axis, flip} -> {type: 'order', id, axis, flip, index, keys}
//
// Each tetrahedron owns 4 vertices (4t .. 4t+3). Its face opposite local
// vertex i is drawn with vertex (i + 1) % 4 last, the provoking vertex of
// WebGL's flat interpolation, so every vertex carries the data of exactly one
// face (its "constrained" flag). Faces are wound outward for back-face culling.

// Outward winding for a positively oriented tet (det[v1-v0, v2-v0, v3-v0] > 0),
// face i (opposite vertex i) listed with vertex (i + 1) % 4 last.
const POSITIVE = [2, 3, 1, 0, 3, 2, 0, 1, 3, 2, 1, 0];
const NEGATIVE = [3, 2, 1, 3, 0, 2, 1, 0, 3, 1, 2, 0];

export const HISTOGRAM_BIN_DEGREES = 5;
export const HISTOGRAM_BINS = 15; // 0..75 degrees (a regular tet has 70.53)

let state = null; // {tets, pos (Float32, 12 per tet), orient (Int8)} of the last build

self.onmessage = (e) => {
  const msg = e.data;
  try {
    if (msg.type === 'build') build(msg);
    else if (msg.type === 'order') {
      if (!state || state.id !== msg.id) return; // superseded
      const order = makeOrder(msg.axis, msg.flip);
      self.postMessage({ type: 'order', id: msg.id, ...order }, [order.index.buffer, order.keys.buffer]);
    }
  } catch (err) {
    self.postMessage({ type: 'failed', id: msg.id, message: String(err?.stack ?? err) });
  }
};

function build(msg) {
  const { id, points, tets, faces, tetAttributes, inputPoints, steinerKinds, origin } = msg;
  const nt = tets.length / 4;
  const [ox, oy, oz] = origin;
  const position = new Float32Array(nt * 12);
  const center = new Float32Array(nt * 12);
  const quality = new Float32Array(nt);
  const orient = new Int8Array(nt);
  const histogram = new Array(HISTOGRAM_BINS).fill(0);
  const nrm = new Float64Array(12);
  const p = new Float64Array(12);

  for (let t = 0; t < nt; t++) {
    let cx = 0;
    let cy = 0;
    let cz = 0;
    for (let j = 0; j < 4; j++) {
      const v = tets[4 * t + j];
      const x = points[3 * v] - ox;
      const y = points[3 * v + 1] - oy;
      const z = points[3 * v + 2] - oz;
      p[3 * j] = x;
      p[3 * j + 1] = y;
      p[3 * j + 2] = z;
      cx += x;
      cy += y;
      cz += z;
    }
    cx *= 0.25;
    cy *= 0.25;
    cz *= 0.25;
    const b = 12 * t;
    for (let k = 0; k < 12; k++) position[b + k] = p[k];
    for (let j = 0; j < 4; j++) {
      center[b + 3 * j] = cx;
      center[b + 3 * j + 1] = cy;
      center[b + 3 * j + 2] = cz;
    }
    // Orientation.
    const ax = p[3] - p[0], ay = p[4] - p[1], az = p[5] - p[2];
    const bx = p[6] - p[0], by = p[7] - p[1], bz = p[8] - p[2];
    const dx = p[9] - p[0], dy = p[10] - p[1], dz = p[11] - p[2];
    const det = ax * (by * dz - bz * dy) - ay * (bx * dz - bz * dx) + az * (bx * dy - by * dx);
    orient[t] = det < 0 ? -1 : 1;
    // Unit outward normals of the 4 faces.
    let degenerate = false;
    for (let i = 0; i < 4; i++) {
      const i0 = 3 * ((i + 1) % 4), i1 = 3 * ((i + 2) % 4), i2 = 3 * ((i + 3) % 4);
      const ux = p[i1] - p[i0], uy = p[i1 + 1] - p[i0 + 1], uz = p[i1 + 2] - p[i0 + 2];
      const wx = p[i2] - p[i0], wy = p[i2 + 1] - p[i0 + 1], wz = p[i2 + 2] - p[i0 + 2];
      let nx = uy * wz - uz * wy;
      let ny = uz * wx - ux * wz;
      let nz = ux * wy - uy * wx;
      const len = Math.hypot(nx, ny, nz);
      if (!(len > 0)) {
        degenerate = true;
        break;
      }
      // Outward: away from vertex i.
      const s = nx * (p[3 * i] - p[i0]) + ny * (p[3 * i + 1] - p[i0 + 1]) + nz * (p[3 * i + 2] - p[i0 + 2]) > 0 ? -1 : 1;
      nrm[3 * i] = (s * nx) / len;
      nrm[3 * i + 1] = (s * ny) / len;
      nrm[3 * i + 2] = (s * nz) / len;
    }
    let minDihedral = 0;
    if (!degenerate) {
      // Interior dihedral angle = pi - angle between the two outward normals,
      // so the smallest one comes from the most opposed pair (smallest dot).
      let minDot = 1;
      for (let k = 0; k < 4; k++) {
        for (let l = k + 1; l < 4; l++) {
          const d = nrm[3 * k] * nrm[3 * l] + nrm[3 * k + 1] * nrm[3 * l + 1] + nrm[3 * k + 2] * nrm[3 * l + 2];
          if (d < minDot) minDot = d;
        }
      }
      minDihedral = 180 - (Math.acos(Math.min(1, Math.max(-1, minDot))) * 180) / Math.PI;
    }
    quality[t] = minDihedral;
    histogram[Math.min(HISTOGRAM_BINS - 1, Math.floor(minDihedral / HISTOGRAM_BIN_DEGREES))]++;
  }

  const flags = constrainedFlags(tets, faces);

  // Regions: a palette index per tet, by distinct attribute value.
  const region = new Uint16Array(nt);
  const regionIndex = new Map();
  if (tetAttributes && tetAttributes.length === nt) {
    for (let t = 0; t < nt; t++) {
      const a = tetAttributes[t];
      let r = regionIndex.get(a);
      if (r === undefined) {
        r = Math.min(regionIndex.size, 65535);
        regionIndex.set(a, r);
      }
      region[t] = r;
    }
  }
  const regionValues = [...regionIndex.keys()];

  // Steiner points (indices >= inputPoints).
  const np = points.length / 3;
  const ns = Math.max(0, np - inputPoints);
  const steinerPosition = new Float32Array(ns * 3);
  const kinds = new Uint8Array(ns);
  for (let s = 0; s < ns; s++) {
    const v = inputPoints + s;
    steinerPosition[3 * s] = points[3 * v] - ox;
    steinerPosition[3 * s + 1] = points[3 * v + 1] - oy;
    steinerPosition[3 * s + 2] = points[3 * v + 2] - oz;
    kinds[s] = steinerKinds ? steinerKinds[s] : 0;
  }

  state = { id, tets, pos: position, orient, nt };
  const order = makeOrder(msg.axis, msg.flip);
  self.postMessage(
    {
      type: 'built',
      id,
      position,
      center,
      flags,
      quality,
      region,
      regionValues,
      histogram,
      steinerPosition,
      steinerKinds: kinds,
      order,
    },
    [
      position.buffer,
      center.buffer,
      flags.buffer,
      quality.buffer,
      region.buffer,
      steinerPosition.buffer,
      kinds.buffer,
      order.index.buffer,
      order.keys.buffer,
    ],
  );
  // position was transferred: keep what ordering needs (per-tet extent).
  state.pos = null;
  state.extent = extentsOf(tets, points, origin);
}

// Per tet and axis: min and max coordinate (relative to origin), 6 per tet.
function extentsOf(tets, points, origin) {
  const nt = tets.length / 4;
  const ext = new Float32Array(nt * 6);
  for (let t = 0; t < nt; t++) {
    for (let a = 0; a < 3; a++) {
      let lo = Infinity;
      let hi = -Infinity;
      for (let j = 0; j < 4; j++) {
        const c = points[3 * tets[4 * t + j] + a] - origin[a];
        if (c < lo) lo = c;
        if (c > hi) hi = c;
      }
      ext[6 * t + 2 * a] = lo;
      ext[6 * t + 2 * a + 1] = hi;
    }
  }
  return ext;
}

// For every tet vertex j: 1 if the face it provokes, face (j + 3) % 4 (the
// face opposite local vertex (j + 3) % 4), is a constrained face.
function constrainedFlags(tets, faces) {
  const nt = tets.length / 4;
  const flags = new Uint8Array(nt * 4);
  const nf = faces ? faces.length / 3 : 0;
  if (nf === 0) return flags;
  let cap = 1;
  while (cap < nf * 2) cap <<= 1;
  const mask = cap - 1;
  const keys = new Uint32Array(cap * 3);
  const used = new Uint8Array(cap);
  const k = [0, 0, 0];
  const sort3 = (a, b, c) => {
    if (a > b) [a, b] = [b, a];
    if (b > c) [b, c] = [c, b];
    if (a > b) [a, b] = [b, a];
    k[0] = a;
    k[1] = b;
    k[2] = c;
  };
  const hash = () => (Math.imul(k[0], 73856093) ^ Math.imul(k[1], 19349663) ^ Math.imul(k[2], 83492791)) & mask;
  for (let f = 0; f < nf; f++) {
    sort3(faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]);
    let h = hash();
    while (used[h]) {
      if (keys[3 * h] === k[0] && keys[3 * h + 1] === k[1] && keys[3 * h + 2] === k[2]) break;
      h = (h + 1) & mask;
    }
    used[h] = 1;
    keys[3 * h] = k[0];
    keys[3 * h + 1] = k[1];
    keys[3 * h + 2] = k[2];
  }
  for (let t = 0; t < nt; t++) {
    const b = 4 * t;
    for (let i = 0; i < 4; i++) {
      sort3(tets[b + ((i + 1) % 4)], tets[b + ((i + 2) % 4)], tets[b + ((i + 3) % 4)]);
      let h = hash();
      while (used[h]) {
        if (keys[3 * h] === k[0] && keys[3 * h + 1] === k[1] && keys[3 * h + 2] === k[2]) {
          flags[b + ((i + 1) % 4)] = 1; // face i is provoked by vertex (i + 1) % 4
          break;
        }
        h = (h + 1) & mask;
      }
    }
  }
  return flags;
}

// Tets sorted so that the visible ones form a prefix: for the kept side below
// the cut (flip false) by their smallest coordinate on the axis, ascending;
// for the side above, by minus their largest. A tet crossing the cut is kept
// whole. Returns the index buffer in that order and the sorted keys.
function makeOrder(axis, flip) {
  const { nt, tets, orient } = state;
  const keys = new Float32Array(nt);
  if (state.extent) {
    const ext = state.extent;
    for (let t = 0; t < nt; t++) keys[t] = flip ? -ext[6 * t + 2 * axis + 1] : ext[6 * t + 2 * axis];
  } else {
    const pos = state.pos;
    for (let t = 0; t < nt; t++) {
      let lo = Infinity;
      let hi = -Infinity;
      for (let j = 0; j < 4; j++) {
        const c = pos[12 * t + 3 * j + axis];
        if (c < lo) lo = c;
        if (c > hi) hi = c;
      }
      keys[t] = flip ? -hi : lo;
    }
  }
  const order = radixSortFloat32(keys);
  const index = new Uint32Array(nt * 12);
  const sorted = new Float32Array(nt);
  for (let s = 0; s < nt; s++) {
    const t = order[s];
    sorted[s] = keys[t];
    const w = orient[t] < 0 ? NEGATIVE : POSITIVE;
    const base = 4 * t;
    const o = 12 * s;
    for (let k = 0; k < 12; k++) index[o + k] = base + w[k];
  }
  void tets;
  return { axis, flip, index, keys: sorted };
}

// Indices 0..n-1 ordered by key ascending (LSD radix sort on the float bits).
function radixSortFloat32(keys) {
  const n = keys.length;
  const bits = new Uint32Array(keys.buffer, keys.byteOffset, n);
  const u = new Uint32Array(n);
  for (let i = 0; i < n; i++) {
    const b = bits[i];
    u[i] = b & 0x80000000 ? ~b >>> 0 : (b | 0x80000000) >>> 0;
  }
  let idx = new Uint32Array(n);
  let tmp = new Uint32Array(n);
  for (let i = 0; i < n; i++) idx[i] = i;
  const count = new Uint32Array(256);
  for (let shift = 0; shift < 32; shift += 8) {
    count.fill(0);
    for (let i = 0; i < n; i++) count[(u[idx[i]] >>> shift) & 255]++;
    let sum = 0;
    for (let c = 0; c < 256; c++) {
      const v = count[c];
      count[c] = sum;
      sum += v;
    }
    for (let i = 0; i < n; i++) {
      const j = idx[i];
      tmp[count[(u[j] >>> shift) & 255]++] = j;
    }
    [idx, tmp] = [tmp, idx];
  }
  return idx;
}
