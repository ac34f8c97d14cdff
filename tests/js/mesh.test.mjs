// tetrahedralize() and friends through the package, against the native CLI:
// the same counts on every model of tests/data (determinism between the
// native and the WebAssembly build), validate() passing, the same error codes
// on invalid input, every input form, options, progress, cancellation,
// writers, and memory returning to the pool between calls.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { before, describe, test } from 'node:test';

import { createInstance, dataDir, readManifest, repoRoot, requireNativeCli, skipNative } from './support.mjs';

let cdt;
let Cdt3dError;
before(async () => ({ cdt, Cdt3dError } = await createInstance()));

const manifest = [...readManifest().values()];
const valid = manifest.filter((r) => r.expected === 'valid' || r.expected === 'valid-plc').map((r) => r.file);
const invalid = manifest.filter((r) => r.expected.startsWith('invalid-')).map((r) => r.file);
const bytesOf = (file) => readFileSync(path.join(dataDir, file));

// `cdt3d mesh FILE --json [args]` from the repository root.
function nativeMesh(file, args = []) {
  const r = spawnSync(requireNativeCli(), ['mesh', path.join('tests', 'data', file), '--json', ...args], {
    cwd: repoRoot,
    encoding: 'utf8',
    maxBuffer: 64 << 20,
  });
  if (r.error) throw r.error;
  return { json: JSON.parse(r.stdout), status: r.status };
}

const COUNTS = ['inputPoints', 'inputFacets', 'inputSegments', 'points', 'tets', 'faces',
  'steinerSegment', 'steinerFacet', 'steinerVolume', 'rule1', 'rule2', 'rule3', 'acuteBoth',
  'splitProjection', 'splitShell', 'splitRemoved',
  'perturbations', 'breakPoints', 'protectSegment', 'protectFacet', 'missingSubfaces', 'regions',
  'missingSegments', 'facetSplits', 'flatFlips', 'flatTets', 'flatEdges', 'mergedFacets'];

describe('every valid model: WASM equals native, and validates', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
  for (const file of valid) {
    test(file, () => {
      const r = cdt.tetrahedralize({ bytes: bytesOf(file), fileName: file }, { validate: true });
      const n = nativeMesh(file);
      assert.equal(n.status, 0);
      for (const k of COUNTS) assert.equal(r.stats[k], n.json[k], `${file}: ${k}`);
      // The same statistics fields as the native --json (which adds ok, phase, edges, delaunay
      // (the result's flag), valid, validation).
      const cliOnly = ['ok', 'phase', 'edges', 'delaunay', 'valid', 'validation'];
      assert.equal(r.delaunay, n.json.delaunay);
      assert.equal(r.delaunay, true);
      assert.deepEqual(Object.keys(r.stats).sort(), Object.keys(n.json).filter((k) => !cliOnly.includes(k)).sort());
      assert.equal(r.points.length, 3 * r.stats.points);
      assert.equal(r.tets.length, 4 * r.stats.tets);
      assert.equal(r.faces.length, 3 * r.stats.faces);
      assert.equal(r.faceFacets.length, r.stats.faces);
      assert.equal(r.tetAttributes.length, r.stats.tets);
      assert.equal(r.steinerKinds.length, r.stats.points - r.inputPoints);
      assert.deepEqual(r.validation, { ok: true, message: '' });
      assert.deepEqual(cdt.validate({ bytes: bytesOf(file), fileName: file }, r), { ok: true, message: '' });
    });
  }
});

describe('every invalid model: the native error code', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
  for (const file of invalid) {
    test(file, () => {
      const n = nativeMesh(file);
      assert.equal(n.status, 1);
      assert.equal(n.json.ok, false);
      assert.throws(
        () => cdt.tetrahedralize({ bytes: bytesOf(file), fileName: file }),
        (e) => {
          assert.ok(e instanceof Cdt3dError);
          assert.equal(e.code, n.json.error.code);
          assert.equal(e.message, n.json.error.message);
          assert.equal(e.facet, n.json.error.facet);
          if (e.code === 'self-intersection') {
            assert.ok(e.facets.length >= 2 && e.facets.length % 2 === 0);
            assert.ok(e.facets.includes(e.facet));
          }
          return true;
        },
      );
    });
  }
});

describe('inputs', () => {
  const tetPoints = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1];
  const tetTriangles = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];

  test('typed arrays and plain arrays give one tet', () => {
    for (const input of [
      { points: new Float64Array(tetPoints), triangles: new Uint32Array(tetTriangles) },
      { points: tetPoints, triangles: tetTriangles },
      { points: tetPoints, facets: tetTriangles.reduce((f, v, i) => (i % 3 ? f[f.length - 1].loops[0].push(v) : f.push({ loops: [[v]] }), f), []) },
    ]) {
      const r = cdt.tetrahedralize(input);
      assert.equal(r.stats.tets, 1);
      assert.equal(r.stats.faces, 4);
      assert.deepEqual([...r.points], tetPoints);
    }
  });

  test('a readPlc() summary can be meshed directly', () => {
    const info = cdt.readPlc(bytesOf('bunny.off'), 'bunny.off');
    const a = cdt.tetrahedralize(info);
    const b = cdt.tetrahedralize({ bytes: bytesOf('bunny.off'), fileName: 'bunny.off' });
    assert.deepEqual(a.tets, b.tets);
  });

  test('a cube with an internal facet as polygons: two regions, attributes 1 and 2', () => {
    const P = [];
    for (const z of [0, 1, 2]) P.push(0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z);
    const quad = (a, b, c, d) => ({ loops: [[a, b, c, d]] });
    const facets = [quad(0, 3, 2, 1), quad(4, 5, 6, 7), quad(8, 9, 10, 11)];
    for (const k of [0, 4]) {
      for (let i = 0; i < 4; ++i) facets.push(quad(k + i, k + ((i + 1) % 4), k + 4 + ((i + 1) % 4), k + 4 + i));
    }
    const r = cdt.tetrahedralize({
      points: P,
      facets,
      regions: [{ point: [0.5, 0.5, 0.5], attribute: 7 }],
    }, { validate: true });
    const attrs = new Set(r.tetAttributes);
    assert.deepEqual([...attrs].sort(), [7, 8]);
  });

  test('a volume hole point removes the inner region', () => {
    const file = 'nested_cubes_cavity.poly';
    const r = cdt.tetrahedralize({ bytes: bytesOf(file), fileName: file }, { validate: true });
    const withHull = cdt.tetrahedralize({ bytes: bytesOf(file), fileName: file }, { keepConvexHull: true });
    assert.ok(r.stats.tets > 0);
    assert.ok(withHull.stats.tets >= r.stats.tets);
  });

  test('bad inputs throw "invalid-argument" naming the problem', () => {
    for (const [input, what] of [
      [null, /input must be an object/],
      [{}, /needs \{bytes, fileName\}/],
      [{ points: [0, 0] , triangles: [] }, /3 numbers per point/],
      [{ points: [0, 0, 0], triangles: [0, 0] }, /3 indices per triangle/],
      [{ points: [0, 0, 0] }, /triangles or input.facets/],
      [{ bytes: new Uint8Array(3) }, /fileName/],
      [{ points: [0, 0, 0], triangles: [-1, 0, 0] }, /non-negative integers/],
    ]) {
      assert.throws(() => cdt.tetrahedralize(input), (e) => e instanceof Cdt3dError && e.code === 'invalid-argument' && what.test(e.message));
    }
  });

  test('an index out of range in arrays is reported with its facet', () => {
    assert.throws(
      () => cdt.tetrahedralize({ points: [0, 0, 0, 1, 0, 0, 0, 1, 0], triangles: [0, 1, 7] }),
      (e) => e instanceof Cdt3dError && e.code === 'index' && e.facet === 0,
    );
  });
});

describe('options', () => {
  const input = () => ({ bytes: bytesOf('cube_ascii.stl'), fileName: 'cube_ascii.stl' });

  test('unknown options and wrong types throw "invalid-argument"', () => {
    for (const options of [
      { keepHull: true },
      { validate: 'yes' },
      { verbosity: 7 },
      { stopAfter: 'later' },
      { degeneracy: 'exact' },
      { degeneracy: 1 },
      { onProgress: 3 },
      { signal: {} },
      [],
    ]) {
      assert.throws(() => cdt.tetrahedralize(input(), options), (e) => e instanceof Cdt3dError && e.code === 'invalid-argument');
    }
  });

  test('degeneracy: "symbolic" is the default and adds no step-3 points; "paper" equals the native --paper-degeneracy', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
    const file = 'chazelle_n3.off';
    const bytes = () => ({ bytes: bytesOf(file), fileName: file });
    const byDefault = cdt.tetrahedralize(bytes());
    const symbolic = cdt.tetrahedralize(bytes(), { degeneracy: 'symbolic' });
    assert.deepEqual(symbolic.tets, byDefault.tets);
    for (const k of ['perturbations', 'breakPoints', 'protectSegment', 'protectFacet']) assert.equal(symbolic.stats[k], 0, k);
    const paper = cdt.tetrahedralize(bytes(), { degeneracy: 'paper', validate: true });
    const n = nativeMesh(file, ['--paper-degeneracy']);
    assert.equal(n.status, 0);
    for (const k of COUNTS) assert.equal(paper.stats[k], n.json[k], `${file} --paper-degeneracy: ${k}`);
  });

  test('flat faces are merged by default; keepTriangles keeps every triangle, like the native --keep-triangles', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
    const file = 'xyz_cube_20mm_binary.stl';
    const bytes = () => ({ bytes: bytesOf(file), fileName: file });
    const merged = cdt.tetrahedralize(bytes(), { validate: true });
    assert.equal(merged.flatFacesMerged, true);
    assert.ok(merged.stats.flatEdges > 0 && merged.stats.mergedFacets > 0);
    assert.equal(merged.flatFaceOf.length, merged.stats.inputFacets);
    // Faces name the smallest input facet of their flat face.
    for (const f of merged.faceFacets) assert.equal(merged.flatFaceOf[f], f);
    const kept = cdt.tetrahedralize(bytes(), { keepTriangles: true, validate: true });
    assert.equal(kept.flatFacesMerged, false);
    assert.equal(kept.stats.flatEdges, 0);
    assert.equal(kept.flatFaceOf.length, 0);
    assert.ok(kept.stats.inputSegments > merged.stats.inputSegments);
    assert.ok(kept.stats.steinerSegment > merged.stats.steinerSegment);
    // validate() merges as the run did: each result checks against the same input.
    assert.equal(cdt.validate(bytes(), merged).ok, true);
    assert.equal(cdt.validate(bytes(), kept).ok, true);
    // The old option name: mergeCoplanarFacets: false keeps the triangles.
    assert.equal(cdt.tetrahedralize(bytes(), { mergeCoplanarFacets: false }).stats.flatEdges, 0);
    const n = nativeMesh(file, ['--keep-triangles']);
    assert.equal(n.status, 0);
    for (const k of COUNTS) assert.equal(kept.stats[k], n.json[k], `${file} --keep-triangles: ${k}`);
  });

  test('stopAfter returns the intermediate mesh with its subsegments', () => {
    const seg = cdt.tetrahedralize(input(), { stopAfter: 'segments' });
    assert.equal(seg.faces.length, 0);
    assert.ok(seg.edges.length / 2 >= seg.stats.inputSegments);
    const del = cdt.tetrahedralize(input(), { stopAfter: 'delaunay' });
    assert.equal(del.stats.points, 8);
  });

  test('progress is monotone, names the phases in order and reaches 1', () => {
    // Step 3 is a phase of its own only in "paper" mode: the default symbolic
    // perturbation has nothing to do there and reports no "degeneracy".
    for (const [degeneracy, expected] of [
      ['symbolic', ['read', 'delaunay', 'segments', 'facets', 'carve', 'done']],
      ['paper', ['read', 'delaunay', 'segments', 'degeneracy', 'facets', 'carve', 'done']],
    ]) {
      const seen = [];
      cdt.tetrahedralize({ bytes: bytesOf('bunny.off'), fileName: 'bunny.off' }, { degeneracy, onProgress: (p) => seen.push(p) });
      const phases = [...new Set(seen.map((p) => p.phase))];
      assert.deepEqual(phases, expected, degeneracy);
      for (let i = 1; i < seen.length; ++i) assert.ok(seen[i].fraction >= seen[i - 1].fraction, degeneracy);
      assert.equal(seen.at(-1).fraction, 1, degeneracy);
    }
  });

  test('an AbortSignal cancels mid-run; the instance works afterwards', () => {
    const controller = new AbortController();
    let phaseAtAbort = null;
    assert.throws(
      () => cdt.tetrahedralize({ bytes: bytesOf('fandisk.off'), fileName: 'fandisk.off' }, {
        signal: controller.signal,
        onProgress: (p) => {
          if (p.phase === 'segments' && !controller.signal.aborted) {
            phaseAtAbort = p.phase;
            controller.abort();
          }
        },
      }),
      (e) => e instanceof Cdt3dError && e.code === 'cancelled',
    );
    assert.equal(phaseAtAbort, 'segments');
    const aborted = new AbortController();
    aborted.abort();
    assert.throws(() => cdt.tetrahedralize(input(), { signal: aborted.signal }), (e) => e.code === 'cancelled');
    assert.equal(cdt.tetrahedralize(input()).stats.tets > 0, true);
  });
});

describe('writers', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
  test('vtk, mesh and node/ele/face text, msh, msh-binary and vtu bytes equal the native CLI output', () => {
    const file = 'cube_internal_facet.poly';
    const r = cdt.tetrahedralize({ bytes: bytesOf(file), fileName: file });
    const dir = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-w-'));
    try {
      for (const [format, exts] of [['vtk', ['vtk']], ['mesh', ['mesh']], ['node', ['node', 'ele', 'face']]]) {
        const prefix = path.join(dir, format);
        const out = spawnSync(requireNativeCli(), ['mesh', path.join(dataDir, file), '-q', '-o', prefix, '--format', format]);
        assert.equal(out.status, 0);
        for (const ext of exts) assert.equal(cdt.write(r, ext), readFileSync(`${prefix}.${ext}`, 'utf8'), ext);
      }
      for (const [format, ext] of [['msh', 'msh'], ['msh-binary', 'msh'], ['vtu', 'vtu']]) {
        const prefix = path.join(dir, format);
        const out = spawnSync(requireNativeCli(), ['mesh', path.join(dataDir, file), '-q', '-o', prefix, '--format', format]);
        assert.equal(out.status, 0);
        const bytes = cdt.write(r, format);
        assert.ok(bytes instanceof Uint8Array, format);
        assert.ok(Buffer.from(bytes).equals(readFileSync(`${prefix}.${ext}`)), format);
      }
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
    assert.throws(() => cdt.write(r, 'stl'), (e) => e.code === 'invalid-argument');
  });

  test('OBJ group names reach the result and become Gmsh physical names, as natively', () => {
    const file = 'cube_groups.obj';
    const r = cdt.tetrahedralize({ bytes: bytesOf(file), fileName: file });
    assert.deepEqual(r.markerNames.map((n) => n.name), ['cube', 'bottom', 'top', 'sides', 'inlet face']);
    const text = new TextDecoder().decode(cdt.write(r, 'msh'));
    assert.match(text, /\n2 5 "inlet face"\n/);
    const dir = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-w-'));
    try {
      const prefix = path.join(dir, 'groups');
      const out = spawnSync(requireNativeCli(), ['mesh', path.join(dataDir, file), '-q', '-o', prefix, '--format', 'msh']);
      assert.equal(out.status, 0);
      assert.equal(text, readFileSync(`${prefix}.msh`, 'utf8'));
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
    // Names given with the arrays come back the same way.
    const plain = cdt.tetrahedralize({
      points: r.points.subarray(0, 3 * r.inputPoints),
      triangles: [0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7],
      markerNames: [{ marker: 0, name: 'skin' }],
    });
    assert.match(new TextDecoder().decode(cdt.write(plain, 'msh')), /"skin"/);
    assert.throws(() => cdt.tetrahedralize({ points: [0, 0, 0], triangles: [], markerNames: [{ marker: 'a' }] }),
      (e) => e.code === 'invalid-argument' && /markerNames\[0\]/.test(e.message));
  });
});

describe('memory', () => {
  test('20 calls in a row do not grow the heap beyond the first call\'s peak by more than 10%', () => {
    const input = { bytes: bytesOf('fandisk.off'), fileName: 'fandisk.off' };
    cdt.tetrahedralize(input);
    const first = cdt.memoryUsage().heapBytes;
    for (let i = 0; i < 19; ++i) cdt.tetrahedralize(input);
    const after = cdt.memoryUsage();
    assert.ok(after.heapBytes <= 1.1 * first, `heap ${after.heapBytes} > 1.1 * ${first}`);
    assert.ok(after.allocatedBytes < 1 << 20, `still allocated: ${after.allocatedBytes}`);
  });

  test('readSurface gives the input triangles, even for a file that fails its checks', () => {
    const ok = cdt.readSurface(bytesOf('l_block.smesh'), 'l_block.smesh');
    assert.equal(ok.error, null);
    assert.equal(ok.triangles.length % 3, 0);
    assert.equal(ok.triangleFacets.length, ok.triangles.length / 3);
    const bad = cdt.readSurface(bytesOf('cube_duplicate_face.off'), 'cube_duplicate_face.off');
    assert.equal(bad.error.code, 'duplicate');
    assert.ok(bad.triangles.length > 0);
  });
});

describe('step 1 alone: delaunay() equals native `cdt3d delaunay`', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
  test('the vertices of every valid model, and random and grid points', () => {
    const inputs = valid.map((file) => {
      const r = cdt.tetrahedralize({ bytes: bytesOf(file), fileName: file }, { stopAfter: 'delaunay' });
      return { name: file, points: r.points.slice(0, 3 * r.inputPoints) };
    });
    let s = 7;
    const rnd = () => ((s = (s * 48271) % 2147483647) / 2147483647);
    inputs.push({ name: 'random', points: Float64Array.from({ length: 3 * 5000 }, rnd) });
    const grid = [];
    for (let x = 0; x < 8; ++x) for (let y = 0; y < 8; ++y) for (let z = 0; z < 8; ++z) grid.push(x, y, z);
    inputs.push({ name: 'grid', points: Float64Array.from(grid) });
    const dir = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-dt-'));
    try {
      for (const { name, points } of inputs) {
        const n = points.length / 3;
        let text = `${n} 3 0 0\n`;
        for (let i = 0; i < n; ++i) text += `${i} ${points[3 * i]} ${points[3 * i + 1]} ${points[3 * i + 2]}\n`;
        const file = path.join(dir, 'p.node');
        writeFileSync(file, text);
        const out = spawnSync(requireNativeCli(), ['delaunay', file, '--json'], { encoding: 'utf8' });
        assert.equal(out.status, 0, out.stderr);
        const native = JSON.parse(out.stdout);
        const w = cdt.delaunay(points);
        assert.equal(w.stats.tets, native.tets, name);
      }
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  });
});
