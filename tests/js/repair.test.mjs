// repair() and tetrahedralize(input, { repair: true }) through the package,
// against the native CLI: every defective model of tests/data of a kind that
// repair fixes meshes and validates after repair, with the same report as
// `cdt3d repair --json`; valid models come out unchanged; results name input
// facets; what cannot be repaired throws a Cdt3dError naming the input.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { before, describe, test } from 'node:test';

import { createInstance, dataDir, readManifest, repoRoot, requireNativeCli, skipNative } from './support.mjs';

let cdt;
let Cdt3dError;
before(async () => ({ cdt, Cdt3dError } = await createInstance()));

const manifest = [...readManifest().values()];
const REPAIRABLE = /^invalid-(selfintersect|duplicate|degenerate|nonplanar)$/;
const defective = manifest.filter((r) => REPAIRABLE.test(r.expected)).map((r) => r.file);
const valid = manifest.filter((r) => r.expected === 'valid' || r.expected === 'valid-plc').map((r) => r.file);
const input = (file) => ({ bytes: readFileSync(path.join(dataDir, file)), fileName: file });

function nativeRepair(file) {
  const r = spawnSync(requireNativeCli(), ['repair', path.join('tests', 'data', file), '--json'], {
    cwd: repoRoot,
    encoding: 'utf8',
  });
  if (r.error) throw r.error;
  return JSON.parse(r.stdout);
}

describe('defective models: repaired, meshed, validated', () => {
  test('there are models of each repairable kind', () => {
    for (const kind of ['selfintersect', 'duplicate', 'degenerate', 'nonplanar']) {
      assert.ok(manifest.some((r) => r.expected === `invalid-${kind}`), kind);
    }
  });
  for (const file of defective) {
    test(file, () => {
      assert.throws(() => cdt.tetrahedralize(input(file)), Cdt3dError);
      const repaired = cdt.repair(input(file));
      assert.equal(repaired.report.changed, true);
      assert.equal(repaired.report.unresolvedPairs, 0);
      assert.equal(repaired.facetSources.length, repaired.facets.length);
      // The repaired PLC passes every input check, meshes and validates.
      const mesh = cdt.tetrahedralize(repaired, { validate: true });
      assert.ok(cdt.validate(repaired, mesh).ok);
      // In one go: faces name input facets.
      const direct = cdt.tetrahedralize(input(file), { repair: true, validate: true });
      assert.equal(direct.repair.changed, true);
      assert.equal(direct.stats.tets, mesh.stats.tets);
      const inputFacets = direct.repair.inputFacets;
      assert.ok(direct.faceFacets.every((f) => f < inputFacets));
      if (!skipNative) {
        const native = nativeRepair(file).repair;
        for (const key of Object.keys(native)) {
          if (key === 'ms' || key === 'changedFacets') continue;
          assert.deepEqual(repaired.report[key], native[key], key);  // regionParts is an array
        }
        assert.equal(repaired.report.changedFacets.length, native.changedFacets);
      }
    });
  }
});

test('valid models come out unchanged', () => {
  for (const file of valid.filter((f) => !/bunny|elephant|rocker|fandisk|spot/.test(f))) {
    const r = cdt.repair(input(file));
    assert.equal(r.report.changed, false, file);
    assert.equal(r.report.changedFacets.length, 0, file);
    assert.equal(r.facets.length, r.report.inputFacets, file);
  }
});

test('the repaired .poly text reads back as the same PLC', () => {
  const r = cdt.repair(input('tjunction_apex.off'));
  const info = cdt.readPlc(new TextEncoder().encode(r.poly), 'repaired.poly');
  assert.equal(info.points, r.points.length / 3);
  assert.equal(info.facets, r.facets.length);
});

test('what repair cannot fix throws a Cdt3dError naming the input', () => {
  assert.throws(
    () => cdt.repair(input('nan_coords.off')),
    (e) => e instanceof Cdt3dError && e.code === 'nan' && e.file === 'nan_coords.off',
  );
  assert.throws(
    () => cdt.tetrahedralize(input('open_cube.off'), { repair: true }),
    (e) => e instanceof Cdt3dError && e.code === 'open-boundary',
  );
  assert.throws(() => cdt.tetrahedralize(input('cube_ascii.stl'), { repair: 1 }), (e) => e.code === 'invalid-argument');
});

test('crossing parts become their union (union: false keeps every cell), as the native CLI', () => {
  const file = 'intersecting_cubes.off';
  const arrangement = cdt.tetrahedralize(input(file), { repair: { union: false }, validate: true });
  const united = cdt.tetrahedralize(input(file), { repair: true, validate: true });
  assert.equal(arrangement.repair.innerFacets, 0);
  assert.equal(united.repair.innerFacets, 12);
  assert.equal(united.repair.unionSkipped, false);
  // The overlap is no cell of its own any more: fewer constrained faces.
  assert.ok(united.stats.faces < arrangement.stats.faces, `${united.stats.faces} vs ${arrangement.stats.faces}`);
  const r = cdt.repair(input(file));
  assert.equal(cdt.repair(input(file), { union: false }).report.innerFacets, 0);
  assert.equal(r.report.innerFacets, 12);
  assert.equal(r.facets.length, r.report.facets);
  if (!skipNative) {
    const native = spawnSync(requireNativeCli(), ['repair', path.join('tests', 'data', file), '--json'], {
      cwd: repoRoot,
      encoding: 'utf8',
    });
    const report = JSON.parse(native.stdout).repair;
    for (const key of ['innerFacets', 'unionSkipped', 'facets', 'points']) assert.equal(r.report[key], report[key], key);
  }
  assert.throws(() => cdt.repair(input(file), { union: 1 }), (e) => e.code === 'invalid-argument' && /union must be a boolean/.test(e.message));
});

// Volume per region attribute of a mesh result.
function volumeByRegion(mesh) {
  const volume = new Map();
  const p = mesh.points;
  for (let t = 0; t < mesh.tets.length / 4; ++t) {
    const [a, b, c, d] = [0, 1, 2, 3].map((k) => 3 * mesh.tets[4 * t + k]);
    const e = [b, c, d].map((q) => [0, 1, 2].map((k) => p[q + k] - p[a + k]));
    const det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    const region = mesh.tetAttributes[t];
    volume.set(region, (volume.get(region) ?? 0) + Math.abs(det) / 6);
  }
  return volume;
}

test('partsAsRegions: each part and their overlap a region, as the native --parts-as-regions', () => {
  const file = 'intersecting_cubes.off';
  const mesh = cdt.tetrahedralize(input(file), { repair: { partsAsRegions: true }, validate: true });
  // Two cubes of side 2 through each other: 7 each alone, 1 where they overlap.
  assert.equal(mesh.repair.parts, 2);
  assert.deepEqual(mesh.repair.regionParts, [[0], [1], [0, 1]]);
  assert.equal(mesh.repair.innerFacets, 0);
  const volume = volumeByRegion(mesh);
  assert.deepEqual([...volume.keys()].sort(), [1, 2, 3]);
  for (const [region, v] of [[1, 7], [2, 7], [3, 1]]) assert.ok(Math.abs(volume.get(region) - v) < 1e-12, `region ${region}: ${volume.get(region)}`);
  // Without the option the report has no regions.
  const plain = cdt.tetrahedralize(input(file), { repair: true }).repair;
  assert.deepEqual([plain.parts, plain.regionParts], [0, []]);
  const repaired = cdt.repair(input(file), { partsAsRegions: true });
  assert.deepEqual(repaired.report.regionParts, [[0], [1], [0, 1]]);
  // Handed back on its own, the PLC carries a region point per region:
  // meshed without the option, the same labels.
  assert.equal(repaired.regions.length, 3);
  const again = volumeByRegion(cdt.tetrahedralize(repaired));
  assert.deepEqual([...again.keys()].sort(), [1, 2, 3]);
  for (const [region, v] of again) assert.ok(Math.abs(v - volume.get(region)) < 1e-12, `region ${region}: ${v}`);
  if (!skipNative) {
    const native = spawnSync(requireNativeCli(), ['mesh', path.join('tests', 'data', file), '--parts-as-regions', '--json'], {
      cwd: repoRoot,
      encoding: 'utf8',
    });
    const report = JSON.parse(native.stdout).repair;
    assert.deepEqual(report.regionParts, mesh.repair.regionParts);
    assert.equal(report.parts, 2);
  }
  assert.throws(
    () => cdt.tetrahedralize(input(file), { repair: { partsAsRegions: true, union: false } }),
    (e) => e.code === 'invalid-argument' && /partsAsRegions keeps the union/.test(e.message),
  );
});

test('fillHoles closes the holes of open surfaces, as the native --fill-holes', () => {
  for (const file of ['open_cube.off', 'bunny_holes.off']) {
    const r = cdt.repair(input(file), { fillHoles: true });
    assert.ok(r.report.filledHoles > 0 && r.report.unfilledHoles === 0, file);
    assert.equal(r.facets.length, r.report.inputFacets + r.report.fillTriangles - r.report.duplicateFacets, file);
    const mesh = cdt.tetrahedralize(r, { validate: true });
    assert.deepEqual(mesh.validation, { ok: true, message: '' }, file);
    const direct = cdt.tetrahedralize(input(file), { repair: { fillHoles: true }, validate: true });
    assert.equal(direct.stats.tets, mesh.stats.tets, file);
    assert.equal(direct.repair.filledHoles, r.report.filledHoles, file);
    if (!skipNative) {
      const native = spawnSync(requireNativeCli(), ['repair', path.join('tests', 'data', file), '--fill-holes', '--json'], {
        cwd: repoRoot,
        encoding: 'utf8',
      });
      const report = JSON.parse(native.stdout).repair;
      for (const key of ['filledHoles', 'fillTriangles', 'fillPoints', 'unfilledHoles', 'facets', 'points']) {
        assert.equal(r.report[key], report[key], `${file}: ${key}`);
      }
    }
  }
  // Without the option holes stay open; bad option values are the caller's error.
  assert.equal(cdt.repair(input('open_cube.off')).report.filledHoles, 0);
  assert.throws(() => cdt.repair(input('open_cube.off'), { fillHoles: 'yes' }), (e) => e.code === 'invalid-argument');
  assert.throws(() => cdt.tetrahedralize(input('open_cube.off'), { repair: { fill: true } }),
    (e) => e.code === 'invalid-argument' && /unknown field "fill"/.test(e.message));
});
