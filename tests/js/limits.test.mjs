// A model too large for the 4 GiB wasm32 heap is refused up front with an
// error that names the limit and what fits (issue 46), not an abort.
import assert from 'node:assert/strict';
import { before, test } from 'node:test';

import { importPackage } from './support.mjs';

let cdt3d;
before(async () => {
  cdt3d = await importPackage();
});

// A closed tetrahedron among n points on a grid that no facet uses.
function pointsAndTetrahedron(n) {
  const points = new Float64Array(3 * n);
  for (let i = 0; i < n; i++) {
    points[3 * i] = i % 1000;
    points[3 * i + 1] = Math.floor(i / 1000) % 1000;
    points[3 * i + 2] = Math.floor(i / 1_000_000);
  }
  const triangles = new Uint32Array([0, 1000, 1, 0, 1, 1_000_000, 0, 1_000_000, 1000, 1, 1000, 1_000_000]);
  return { points, triangles };
}

test('a model of 3 million points is refused with a too-large error naming the heap limit', async () => {
  const cdt = await cdt3d.createCdt3d();
  // The size check counts the points the pipeline would insert, before any
  // work.
  const { points, triangles } = pointsAndTetrahedron(3_000_000);
  let thrown;
  try {
    cdt.tetrahedralize({ points, triangles });
  } catch (e) {
    thrown = e;
  }
  assert.ok(thrown instanceof cdt3d.Cdt3dError, `threw ${thrown?.stack ?? thrown}`);
  assert.equal(thrown.code, 'too-large');
  assert.match(thrown.message, /3000000 points/);
  assert.match(thrown.message, /limited to 4\.0 GiB/);
  assert.match(thrown.message, /up to about [0-9.]+ million points/);
  // The instance stays usable.
  const small = cdt.tetrahedralize({
    points: new Float64Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]),
    triangles: new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]),
  });
  assert.equal(small.stats.tets, 1);
});

test('validation needs more heap: 2 million points fit without it, and are refused with it', async () => {
  const cdt = await cdt3d.createCdt3d();
  const { points, triangles } = pointsAndTetrahedron(2_000_000);
  let thrown;
  try {
    cdt.tetrahedralize({ points, triangles }, { validate: true });
  } catch (e) {
    thrown = e;
  }
  assert.ok(thrown instanceof cdt3d.Cdt3dError, `threw ${thrown?.stack ?? thrown}`);
  assert.equal(thrown.code, 'too-large');
  assert.match(thrown.message, /2000000 points/);
  assert.match(thrown.message, /meshing it and validating the mesh needs about/);
  assert.match(thrown.message, /million triangles\) with validation/);
  // Without validation the same model is under the limit: the message of a
  // 3M-point model says so (2.4 million points fit).
  const limit = Number(/up to about ([0-9.]+) million points/.exec(thrown.message)[1]);
  assert.ok(limit > 2, `limit without validation ${limit} million points`);
});
