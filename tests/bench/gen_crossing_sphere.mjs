// Writes an OFF test surface for the repair benchmark: a UV sphere of radius
// 1 with about 100k triangles and a closed box (12 triangles) that passes
// through its surface, tilted so that nothing is aligned, which makes a few
// hundred crossing triangle pairs.
// usage: node tests/bench/gen_crossing_sphere.mjs OUT.off [rings]
import { writeFileSync } from 'node:fs';

const out = process.argv[2];
const rings = Number(process.argv[3] ?? 224);
if (!out) {
  console.error('usage: node gen_crossing_sphere.mjs OUT.off [rings]');
  process.exit(2);
}
const pts = [];
const tris = [];
// Sphere: poles plus rings x segments, segments = rings.
const seg = rings;
pts.push([0, 0, 1]);
for (let i = 1; i < rings; i++) {
  const th = (Math.PI * i) / rings;
  for (let j = 0; j < seg; j++) {
    const ph = (2 * Math.PI * j) / seg;
    pts.push([Math.sin(th) * Math.cos(ph), Math.sin(th) * Math.sin(ph), Math.cos(th)]);
  }
}
pts.push([0, 0, -1]);
const south = pts.length - 1;
const at = (i, j) => 1 + (i - 1) * seg + (j % seg);
for (let j = 0; j < seg; j++) tris.push([0, at(1, j), at(1, j + 1)]);
for (let i = 1; i < rings - 1; i++)
  for (let j = 0; j < seg; j++) {
    tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
    tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
  }
for (let j = 0; j < seg; j++) tris.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
// Box: half-size 0.37 around (0.93, 0.05, 0.11), rotated about a tilted axis.
const c = [0.93, 0.05, 0.11], h = 0.37, a = 0.3;
const rot = ([x, y, z]) => {
  const [ca, sa] = [Math.cos(a), Math.sin(a)];
  const [x1, y1] = [ca * x - sa * y, sa * x + ca * y];
  const [cb, sb] = [Math.cos(a / 2), Math.sin(a / 2)];
  return [cb * x1 + sb * z, y1, -sb * x1 + cb * z];
};
const base = pts.length;
for (let k = 0; k < 8; k++) {
  const p = rot([k & 1 ? h : -h, k & 2 ? h : -h, k & 4 ? h : -h]);
  pts.push([p[0] + c[0], p[1] + c[1], p[2] + c[2]]);
}
const quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
for (const [p, q, r, s] of quads) {
  tris.push([base + p, base + q, base + r]);
  tris.push([base + p, base + r, base + s]);
}
const lines = [`OFF`, `${pts.length} ${tris.length} 0`];
for (const p of pts) lines.push(p.map((x) => x.toPrecision(17)).join(' '));
for (const t of tris) lines.push(`3 ${t.join(' ')}`);
writeFileSync(out, lines.join('\n') + '\n');
console.log(`${out}: ${pts.length} points, ${tris.length} triangles`);
