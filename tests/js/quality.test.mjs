// Quality refinement through the package (issue 17): the `quality` option of
// tetrahedralize (checks, defaults, `true`), the "refine" phase, the new
// statistics, the same counts as the native CLI, the worker, and the Node
// CLI (wasm/cli.js) with the native CLI's words and messages.
//
// Tests named "... [needs refinement]" check what refinement does (points
// added, volumes bounded, quality improved); the others check that the
// options and statistics get through.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { before, describe, test } from 'node:test';

import { createInstance, dataDir, packageDir, readManifest, repoRoot, requireNativeCli, skipNative } from './support.mjs';

let cdt;
let Cdt3dError;
before(async () => ({ cdt, Cdt3dError } = await createInstance()));

const CUBE = 'cube_ascii.stl'; // the unit cube, 12 triangles
const BUNNY = 'bunny.off';
const input = (file) => ({ bytes: readFileSync(path.join(dataDir, file)), fileName: file });

const NEW_COUNTS = ['refineSegment', 'refineFacet', 'refineVolume', 'refineSkipped', 'refineSmallAngle', 'refineCapped', 'improveFlips', 'improveSmooths', 'improvePoints'];
const HISTOGRAMS = ['radiusEdgeHistogram', 'dihedralHistogram', 'radiusEdgeHistogramBefore', 'dihedralHistogramBefore'];
const sum = (a) => a.reduce((x, y) => x + y, 0);
// Points added by refinement and by the improvement pass (on by default).
const added = (s) => s.refineSegment + s.refineFacet + s.refineVolume + s.improvePoints;
// Statistics without the times, which differ from run to run.
const comparable = (s) => Object.fromEntries(Object.entries(s).filter(([k]) => !/^ms[A-Z]/.test(k)));

function tetVolume(r, t) {
  const p = [0, 1, 2, 3].map((k) => r.points.subarray(3 * r.tets[4 * t + k], 3 * r.tets[4 * t + k] + 3));
  const [u, v, w] = [0, 1, 2].map((k) => [0, 1, 2].map((i) => p[k][i] - p[3][i]));
  return Math.abs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6;
}

describe('the quality option', () => {
  test('bad values throw "invalid-argument" naming the field and the rule', () => {
    for (const [quality, says] of [
      ['yes', /option "quality" must be true or an object with any of radiusEdge, maxVolume, minDihedral, maxPoints, got a string/],
      [2, /option "quality" must be true or an object/],
      [[], /option "quality" must be true or an object .* got an Array/],
      [{ ratio: 2 }, /unknown option "quality\.ratio" \(known: radiusEdge, maxVolume, minDihedral, maxPoints\)/],
      [{ radiusEdge: '2' }, /option "quality\.radiusEdge" must be a number, got a string/],
      [{ radiusEdge: 0.5 }, /option quality\.radiusEdge: The radius-edge bound .* >= 1 \(got 0\.5/],
      [{ radiusEdge: NaN }, /option quality\.radiusEdge: .*got -?nan/],
      [{ radiusEdge: Infinity }, /option quality\.radiusEdge: /],
      [{ maxVolume: 0 }, /option quality\.maxVolume: The maximum tet volume must be positive/],
      [{ maxVolume: -3 }, /option quality\.maxVolume: .*got -3/],
      [{ minDihedral: 71 }, /option quality\.minDihedral: .*between 0 and 70 degrees \(got 71/],
      [{ minDihedral: -1 }, /option quality\.minDihedral: /],
      [{ maxPoints: -1 }, /option "quality\.maxPoints" must be a whole number >= 0/],
      [{ maxPoints: 1.5 }, /option "quality\.maxPoints" must be a whole number >= 0 .*got 1\.5/],
    ]) {
      assert.throws(
        () => cdt.tetrahedralize(input(CUBE), { quality }),
        (e) => e instanceof Cdt3dError && e.code === 'invalid-argument' && says.test(e.message),
        `quality: ${JSON.stringify(quality)}`,
      );
    }
    // Options are checked before the input is read: an empty file does not hide them.
    assert.throws(
      () => cdt.tetrahedralize({ bytes: new Uint8Array(0), fileName: 'empty.stl' }, { quality: { radiusEdge: 0 } }),
      (e) => e.code === 'invalid-argument' && /quality\.radiusEdge/.test(e.message),
    );
    assert.ok(cdt.tetrahedralize(input(CUBE), { quality: true }).stats.tets > 0, 'the instance works afterwards');
  });

  test('true, {} and the defaults written out are one run; false and null are none', () => {
    const byTrue = cdt.tetrahedralize(input(CUBE), { quality: true });
    for (const quality of [{}, { radiusEdge: 2, maxVolume: -1, minDihedral: 15, maxPoints: 0 }, { radiusEdge: undefined }]) {
      const r = cdt.tetrahedralize(input(CUBE), { quality });
      assert.deepEqual(r.tets, byTrue.tets, JSON.stringify(quality));
      assert.deepEqual(comparable(r.stats), comparable(byTrue.stats), JSON.stringify(quality));
    }
    const plain = cdt.tetrahedralize(input(CUBE));
    for (const quality of [false, null, undefined]) {
      const r = cdt.tetrahedralize(input(CUBE), { quality });
      assert.deepEqual(comparable(r.stats), comparable(plain.stats), String(quality));
      assert.equal(r.stats.msRefine, 0, String(quality));
    }
  });

  test('progress reports "refine" between "carve" and "done" when quality is on, and stopAfter takes "refine"', () => {
    const seen = [];
    cdt.tetrahedralize(input(CUBE), { quality: { maxVolume: 0.05 }, onProgress: (p) => seen.push(p) });
    assert.deepEqual([...new Set(seen.map((p) => p.phase))], ['read', 'delaunay', 'segments', 'facets', 'carve', 'refine', 'done']);
    for (let i = 1; i < seen.length; ++i) assert.ok(seen[i].fraction >= seen[i - 1].fraction, `monotone at ${i}`);
    assert.equal(seen.at(-1).fraction, 1);
    const plain = [];
    cdt.tetrahedralize(input(CUBE), { onProgress: (p) => plain.push(p.phase) });
    assert.ok(!plain.includes('refine'), 'no "refine" phase without quality');
    const stopped = cdt.tetrahedralize(input(CUBE), { quality: { maxVolume: 0.05 }, stopAfter: 'refine' });
    const done = cdt.tetrahedralize(input(CUBE), { quality: { maxVolume: 0.05 } });
    assert.deepEqual(stopped.tets, done.tets);
  });
});

describe('the statistics', () => {
  test('every new field is there; histograms count the tets; "before" is the CDT before refinement', () => {
    const plain = cdt.tetrahedralize(input(BUNNY));
    const refined = cdt.tetrahedralize(input(BUNNY), { quality: true });
    for (const [name, r] of [['plain', plain], ['refined', refined]]) {
      const s = r.stats;
      for (const k of NEW_COUNTS) assert.ok(Number.isInteger(s[k]) && s[k] >= 0, `${name}: ${k} = ${s[k]}`);
      assert.ok(s.refineCapped === 0 || s.refineCapped === 1, `${name}: refineCapped`);
      for (const k of HISTOGRAMS) {
        assert.ok(Array.isArray(s[k]) && s[k].length === 10 && s[k].every(Number.isInteger), `${name}: ${k}`);
      }
      assert.equal(sum(s.radiusEdgeHistogram), s.tets, `${name}: radiusEdgeHistogram counts every tet`);
      assert.equal(sum(s.dihedralHistogram), s.tets, `${name}: dihedralHistogram counts every tet`);
      assert.ok(s.minDihedral >= 0 && s.minDihedral <= s.maxDihedral, name);
      // Refinement points are Steiner points of their kind.
      assert.equal(s.points, plain.stats.points + added(s), `${name}: points`);
      assert.ok(s.steinerSegment >= s.refineSegment && s.steinerFacet >= s.refineFacet && s.steinerVolume >= s.refineVolume, name);
      assert.ok(Number.isFinite(s.msRefine) && s.msRefine >= 0, name);
    }
    const p = plain.stats;
    const s = refined.stats;
    // Without refinement nothing is added and "before" equals the final quality.
    for (const k of NEW_COUNTS) assert.equal(p[k], 0, `plain: ${k}`);
    assert.equal(p.msRefine, 0);
    assert.deepEqual(p.radiusEdgeHistogramBefore, p.radiusEdgeHistogram);
    assert.deepEqual(p.dihedralHistogramBefore, p.dihedralHistogram);
    assert.equal(p.minDihedralBefore, p.minDihedral);
    // With it, "before" is the plain CDT's quality.
    assert.deepEqual(s.radiusEdgeHistogramBefore, p.radiusEdgeHistogram);
    assert.deepEqual(s.dihedralHistogramBefore, p.dihedralHistogram);
    assert.equal(s.minDihedralBefore, p.minDihedral);
  });

  test('bunny with quality: more tets, points inside, quality no worse than before [needs refinement]', () => {
    const plain = cdt.tetrahedralize(input(BUNNY));
    const r = cdt.tetrahedralize(input(BUNNY), { quality: true, validate: true });
    const s = r.stats;
    assert.ok(s.tets > plain.stats.tets, `tets ${s.tets} > ${plain.stats.tets}`);
    assert.ok(s.refineVolume > 0, `refineVolume ${s.refineVolume}`);
    // Tets with radius-edge > 2 (bins from 2-3 on): a smaller share.
    const bad = (h) => sum(h.slice(3)) / sum(h);
    assert.ok(bad(s.radiusEdgeHistogram) < bad(s.radiusEdgeHistogramBefore), 'fewer tets with radius-edge > 2');
    assert.ok(s.msRefine > 0);
    assert.deepEqual(r.validation, { ok: true, message: '' });
  });

  test('minDihedral: the improvement pass raises the smallest angle and gives up the Delaunay property', () => {
    const plain = cdt.tetrahedralize(input(BUNNY), { quality: { radiusEdge: 1.414, minDihedral: 0 } });
    const r = cdt.tetrahedralize(input(BUNNY), { quality: { radiusEdge: 1.414, minDihedral: 15 }, validate: true });
    // 15 is the default: the pass runs unless minDihedral is 0.
    const byDefault = cdt.tetrahedralize(input(BUNNY), { quality: { radiusEdge: 1.414 } });
    assert.deepEqual(byDefault.tets, r.tets);
    const s = r.stats;
    assert.equal(plain.delaunay, true);
    assert.equal(r.delaunay, false);
    assert.ok(s.improveFlips > 0 && s.improveSmooths > 0 && s.improvePoints > 0, JSON.stringify(s));
    assert.ok(plain.stats.minDihedral < 0.5, `without the pass ${plain.stats.minDihedral}`);
    assert.ok(s.minDihedral > 2, `with it ${s.minDihedral}`);
    assert.equal(s.flatTets, 0);
    // With the pass, split points go in unconditionally (refine.cpp), so refinement itself
    // differs; the points the pass added are volume points.
    assert.ok(s.steinerVolume >= s.improvePoints);
    // Facets and segments still covered (validate skips the Delaunay check for such a result) ...
    assert.deepEqual(r.validation, { ok: true, message: '' });
    assert.equal(cdt.validate(input(BUNNY), r).ok, true);
    // ... which would fail if the result claimed to be Delaunay.
    const claimed = cdt.validate(input(BUNNY), { ...r, delaunay: true });
    assert.equal(claimed.ok, false);
    assert.match(claimed.message, /not locally Delaunay/);
  });

  test('maxVolume bounds every tet; maxPoints stops refinement [needs refinement]', () => {
    const plain = cdt.tetrahedralize(input(CUBE));
    const r = cdt.tetrahedralize(input(CUBE), { quality: { maxVolume: 0.01 } });
    assert.ok(r.stats.tets >= 100, `tets ${r.stats.tets}`);
    for (let t = 0; t < r.stats.tets; ++t) assert.ok(tetVolume(r, t) <= 0.01, `tet ${t}: volume ${tetVolume(r, t)}`);
    assert.equal(cdt.validate(input(CUBE), r).ok, true);
    assert.equal(r.stats.refineCapped, 0);
    const capped = cdt.tetrahedralize(input(CUBE), { quality: { maxVolume: 0.0001, maxPoints: 40 } });
    assert.equal(capped.stats.refineCapped, 1);
    assert.ok(added(capped.stats) > 0 && added(capped.stats) <= 40, `added ${added(capped.stats)}`);
    assert.equal(capped.stats.points, plain.stats.points + added(capped.stats));
  });
});

// `cdt3d mesh FILE ARGS` of the native CLI (tests/data) or of wasm/cli.js.
function run(command, file, args) {
  const [exe, pre] = command === 'native' ? [requireNativeCli(), []] : [process.execPath, [path.join(packageDir, 'cli.js')]];
  const r = spawnSync(exe, [...pre, 'mesh', path.join('tests', 'data', file), ...args], { cwd: repoRoot, encoding: 'utf8', maxBuffer: 64 << 20 });
  if (r.error) throw r.error;
  return r;
}

describe('the command lines', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
  const CASES = [
    [CUBE, ['--max-volume', '0.01']],
    [CUBE, ['--quality', '1.5', '--max-volume', '0.002', '--max-points', '30', '--min-dihedral', '0']],
    [BUNNY, ['--quality']],
    [BUNNY, ['--quality', '1.414', '--min-dihedral', '15']],
  ];

  test('WASM, the Node CLI and the native CLI give the same statistics with the quality options', () => {
    const options = {
      '--quality': (q, v) => (q.radiusEdge = Number(v)),
      '--max-volume': (q, v) => (q.maxVolume = Number(v)),
      '--min-dihedral': (q, v) => (q.minDihedral = Number(v)),
      '--max-points': (q, v) => (q.maxPoints = Number(v)),
    };
    for (const [file, args] of CASES) {
      const what = `${file} ${args.join(' ')}`;
      const native = run('native', file, [...args, '--json']);
      assert.equal(native.status, 0, `${what}: ${native.stderr}`);
      const n = JSON.parse(native.stdout);
      const node = run('node', file, [...args, '--json']);
      assert.equal(node.status, 0, `${what}: ${node.stderr}`);
      const j = JSON.parse(node.stdout);
      const quality = {};
      args.forEach((a, i) => options[a] && i + 1 < args.length && !args[i + 1].startsWith('-') && options[a](quality, args[i + 1]));
      const api = cdt.tetrahedralize(input(file), { quality }).stats;
      for (const [k, v] of Object.entries(comparable(api))) {
        if (typeof v === 'number' && !Number.isInteger(v)) continue; // angles: printed rounded
        assert.deepEqual(n[k], v, `${what}: native ${k}`);
        assert.deepEqual(j[k], v, `${what}: node CLI ${k}`);
      }
    }
  });

  test('every valid model of tests/data refines (with the improvement pass) to the same counts natively and in WASM', () => {
    const valid = [...readManifest().values()].filter((r) => r.expected === 'valid' || r.expected === 'valid-plc').map((r) => r.file);
    assert.ok(valid.length > 20);
    for (const file of valid) {
      const native = run('native', file, ['--quality', '--min-dihedral', '15', '--json']);
      assert.equal(native.status, 0, `${file}: ${native.stderr}`);
      const n = JSON.parse(native.stdout);
      const api = cdt.tetrahedralize(input(file), { quality: { minDihedral: 15 } }).stats;
      // thin_plate's merged faces need points at its thickness's scale all
      // over (about 400k): within the point limit too.
      assert.ok(api.tets > 0 && api.refineCapped === 0, file);
      for (const [k, v] of Object.entries(comparable(api))) {
        if (typeof v === 'number' && !Number.isInteger(v)) continue; // angles: printed rounded
        assert.deepEqual(n[k], v, `${file}: native ${k}`);
      }
    }
  });

  test('--stats prints the same refinement lines in both CLIs', () => {
    const [file, args] = CASES[1];
    const keep = (text) => text.split('\n').filter((l) => /^ {2}(Quality refinement|Sliver improvement|Radius-edge ratios|Min dihedral\/tet|Dihedral angles)/.test(l));
    const native = run('native', file, [...args, '--stats']);
    const node = run('node', file, [...args, '--stats']);
    assert.equal(native.status, 0, native.stderr);
    assert.equal(node.status, 0, node.stderr);
    const lines = keep(native.stdout);
    assert.equal(lines.length, 7, native.stdout);
    assert.deepEqual(keep(node.stdout), lines);
    assert.match(node.stdout, /Time \(ms\): .*carve [0-9.]+, refine [0-9.]+, total/);
  });

  test('bad values are usage errors (exit 2) with the same message in both CLIs', () => {
    for (const args of [
      ['--quality', '0.5'],
      ['--max-volume', '0'],
      ['--max-volume', 'abc'],
      ['--max-volume'],
      ['--min-dihedral', '75'],
      ['--max-points', '-5'],
      ['--quality', '--stop-after', 'facets'],
    ]) {
      const what = args.join(' ');
      const native = run('native', CUBE, args);
      const node = run('node', CUBE, args);
      assert.equal(native.status, 2, `native ${what}`);
      assert.equal(node.status, 2, `node ${what}`);
      const first = (text) => text.split('\n')[0].replace(/^cdt3d( mesh)?: /, '');
      assert.match(native.stderr, new RegExp(`^cdt3d mesh: ${args[0]}`), what);
      assert.equal(first(node.stderr), first(native.stderr), what);
      assert.equal(node.stdout, '', `node ${what}: nothing meshed`);
    }
  });
});

test('the worker passes the quality option through', { timeout: 60_000 }, async () => {
  const { meshInWorker } = await import('cdt3d/worker');
  const expected = cdt.tetrahedralize(input(CUBE), { quality: { maxVolume: 0.01 } });
  const phases = [];
  const got = await meshInWorker(readFileSync(path.join(dataDir, CUBE)), { quality: { maxVolume: 0.01 } }, {
    fileName: CUBE,
    onProgress: ({ phase }) => phases.at(-1) !== phase && phases.push(phase),
  });
  assert.deepEqual(got.tets, expected.tets);
  assert.deepEqual(comparable(got.stats), comparable(expected.stats));
  assert.ok(phases.includes('refine'), `phases: ${phases}`);
  const err = await meshInWorker(readFileSync(path.join(dataDir, CUBE)), { quality: { minDihedral: 90 } }, { fileName: CUBE }).then(
    () => assert.fail('should reject'),
    (e) => e,
  );
  assert.ok(err instanceof Cdt3dError);
  assert.equal(err.code, 'invalid-argument');
  assert.match(err.message, /quality\.minDihedral/);
});
