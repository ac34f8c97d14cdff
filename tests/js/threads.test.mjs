// The two-thread module that Node gets by default (wasm/node.js): chosen as
// documented, the same results as the single-threaded module, errors from
// the work on the second thread reported like any other, and a process that
// ends when the caller is done (the pool's worker thread must not keep it
// alive).
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { before, describe, test } from 'node:test';

import { dataDir, importPackage, packageFile, repoRoot } from './support.mjs';

let pkg;
before(async () => {
  pkg = await importPackage();
});

const bytesOf = (file) => readFileSync(path.join(dataDir, file));

// Everything of a result but the clocks.
function withoutClocks(result) {
  const stats = Object.fromEntries(Object.entries(result.stats).filter(([k]) => !k.startsWith('ms')));
  return { ...result, stats };
}

describe('which module Node gets', () => {
  test('two threads by default, one with threads: false or a caller-given .wasm', async () => {
    assert.equal((await pkg.createCdt3d()).threaded, true);
    assert.equal((await pkg.createCdt3d({ threads: true })).threaded, true);
    assert.equal((await pkg.createCdt3d({ threads: false })).threaded, false);
    const own = await pkg.createCdt3d({ wasmBinary: packageFile('dist/cdt3d.wasm') });
    assert.equal(own.threaded, false);
  });

  test('threads must be a boolean', async () => {
    await assert.rejects(pkg.createCdt3d({ threads: 'yes' }), (e) => {
      assert.ok(e instanceof pkg.Cdt3dError);
      assert.equal(e.code, 'invalid-argument');
      assert.match(e.message, /threads must be a boolean, got string/);
      return true;
    });
  });
});

// The input fails with the same self-intersection error on one thread and on two.
async function assertSameSelfIntersection(input) {
  const errors = [];
  for (const threads of [false, true]) {
    const cdt = await pkg.createCdt3d({ threads });
    assert.throws(() => cdt.tetrahedralize(input), (e) => {
      assert.ok(e instanceof pkg.Cdt3dError);
      errors.push(e.toJSON());
      return true;
    });
  }
  assert.equal(errors[0].code, 'self-intersection');
  assert.deepEqual(errors[1], errors[0]);
}

describe('the same results on two threads', () => {
  // Above the pipeline's thresholds for the work beside step 1: 1,000 facets
  // (self-intersection test), 2,000 facets (facet triangulation) and 20,000
  // tets (statistics), so all three run on the second thread when the
  // machine has two cores.
  for (const file of ['elephant.obj', 'bunny.off', 'plate_holes_binary.stl']) {
    test(file, async () => {
      const one = await pkg.createCdt3d({ threads: false });
      const two = await pkg.createCdt3d();
      const input = { bytes: bytesOf(file), fileName: file };
      const a = one.tetrahedralize(input, { validate: true });
      const b = two.tetrahedralize(input, { validate: true });
      assert.ok(b.stats.tets > 0);
      assert.deepEqual(withoutClocks(b), withoutClocks(a));
      if (file === 'elephant.obj') assert.ok(b.stats.tets >= 20000, 'elephant no longer exercises the split statistics');
    });
  }

  test('a self-intersection found on the second thread is the same error', async () => {
    // Two copies of elephant.obj, the second shifted by a tenth of its size:
    // thousands of facets, so the test runs beside step 1.
    const text = readFileSync(path.join(dataDir, 'elephant.obj'), 'utf8').split('\n');
    const vertices = text.filter((l) => l.startsWith('v '));
    const faces = text.filter((l) => l.startsWith('f '));
    const n = vertices.length;
    const shifted = vertices.map((l) => {
      const [, x, y, z] = l.trim().split(/\s+/).map(Number);
      return `v ${x + 0.05} ${y + 0.03} ${z}`;
    });
    const renumber = (l) =>
      'f ' + l.slice(2).trim().split(/\s+/).map((c) => String(Number(c.split('/')[0]) + n)).join(' ');
    const obj = [...vertices, ...shifted, ...faces, ...faces.map(renumber)].join('\n');
    await assertSameSelfIntersection({ bytes: new TextEncoder().encode(obj), fileName: 'two_elephants.obj' });
  });

  // A box whose top is a k x k grid at pseudo-random heights, its sides
  // polygons through the grid's border: over 20,000 points, so step 1
  // inserts its later rounds on two threads and the self-intersection test
  // runs after it, beside step 2. With `cut`, a triangle through the box.
  function bumpyBoxOff(k, cut) {
    const v = [];
    const f = [];
    for (let i = 0; i < k; i++)
      for (let j = 0; j < k; j++) {
        const s = Math.sin(i * 12.9898 + j * 78.233) * 43758.5453;
        v.push(`${i} ${j} ${10 + 0.5 * (s - Math.floor(s))}`);
      }
    const g = (i, j) => i * k + j;
    const m = k - 1;
    const b = [k * k, k * k + 1, k * k + 2, k * k + 3];
    v.push(`0 0 0`, `${m} 0 0`, `${m} ${m} 0`, `0 ${m} 0`);
    f.push(`4 ${b[0]} ${b[3]} ${b[2]} ${b[1]}`);
    for (let i = 0; i < m; i++)
      for (let j = 0; j < m; j++) {
        f.push(`3 ${g(i, j)} ${g(i + 1, j)} ${g(i + 1, j + 1)}`);
        f.push(`3 ${g(i, j)} ${g(i + 1, j + 1)} ${g(i, j + 1)}`);
      }
    const border = [
      (t) => g(t, 0),
      (t) => g(m, t),
      (t) => g(m - t, m),
      (t) => g(0, m - t),
    ];
    for (let side = 0; side < 4; side++) {
      const loop = [b[side], b[(side + 1) % 4]];
      for (let t = m; t >= 0; t--) loop.push(border[side](t));
      f.push(`${loop.length} ${loop.join(' ')}`);
    }
    if (cut) {
      v.push('-50 -50 5', '300 -50 5', '72 300 5');
      f.push(`3 ${v.length - 3} ${v.length - 2} ${v.length - 1}`);
    }
    return new TextEncoder().encode(`OFF\n${v.length} ${f.length} 0\n${v.join('\n')}\n${f.join('\n')}\n`);
  }

  test('20,000 points and more: step 1 on two threads, the same mesh and the same error', async () => {
    const one = await pkg.createCdt3d({ threads: false });
    const two = await pkg.createCdt3d();
    const input = { bytes: bumpyBoxOff(145, false), fileName: 'bumpy_box.off' };
    const a = one.tetrahedralize(input, { validate: true });
    const b = two.tetrahedralize(input, { validate: true });
    assert.ok(b.stats.inputPoints >= 20000);
    assert.deepEqual(withoutClocks(b), withoutClocks(a));
    await assertSameSelfIntersection({ bytes: bumpyBoxOff(145, true), fileName: 'bumpy_box_cut.off' });
  });
});

test('a process that used the two-thread module ends by itself', () => {
  const script = `
    import { readFileSync } from 'node:fs';
    import { createCdt3d } from 'cdt3d';
    const cdt = await createCdt3d();
    const r = cdt.tetrahedralize({ bytes: readFileSync(${JSON.stringify(path.join(dataDir, 'bunny.off'))}), fileName: 'bunny.off' });
    console.log(JSON.stringify({ threaded: cdt.threaded, tets: r.stats.tets }));`;
  const r = spawnSync(process.execPath, ['--input-type=module', '-e', script], {
    cwd: repoRoot,
    encoding: 'utf8',
    timeout: 60000,
  });
  assert.equal(r.signal, null, 'the process did not end within 60 s');
  assert.equal(r.status, 0, r.stderr);
  const got = JSON.parse(r.stdout);
  assert.equal(got.threaded, true);
  assert.ok(got.tets > 0);
});

test('the Node CLI prints the same result with --one-thread', () => {
  const runCli = (args) => {
    const r = spawnSync(process.execPath, [path.join(repoRoot, 'wasm', 'cli.js'), 'mesh', path.join(dataDir, 'elephant.obj'), '--json', ...args], {
      cwd: repoRoot,
      encoding: 'utf8',
      maxBuffer: 64 << 20,
      timeout: 120000,
    });
    assert.equal(r.status, 0, r.stderr);
    return withoutClocks({ stats: JSON.parse(r.stdout) }).stats;
  };
  const two = runCli([]);
  assert.ok(two.tets > 0);
  assert.deepEqual(runCli(['--one-thread']), two);
});
