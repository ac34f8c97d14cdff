// The package as users get it: `npm pack` ships exactly the listed files, and
// the tarball installed into an empty project works when imported by name.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, test } from 'node:test';

import { corpusFile, importPackage, packageDir, repoRoot } from './support.mjs';

const SHIPPED = [
  'LICENSE', 'README.md', 'api.js', 'cdt3d.d.ts', 'cli.js', 'dist/cdt3d.js', 'dist/cdt3d.wasm',
  'dist/node/cdt3d.js', 'dist/node/cdt3d.wasm', 'dist/node/cdt3d.worker.js', 'dist/node/package.json',
  'dist/threads/cdt3d.js', 'dist/threads/cdt3d.wasm', 'dist/threads/cdt3d.worker.js',
  'index.js', 'node.js', 'package.json', 'warm-up.js', 'worker-entry.js', 'worker.d.ts', 'worker.js',
];

const tmp = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-pack-'));
after(() => rmSync(tmp, { recursive: true, force: true }));

function npm(args, cwd) {
  const r = spawnSync('npm', [...args, '--no-audit', '--no-fund', '--loglevel=error'], { cwd, encoding: 'utf8' });
  assert.equal(r.status, 0, `npm ${args.join(' ')} failed:\n${r.stdout}\n${r.stderr}`);
  return r.stdout;
}

let tarball;

test('npm pack ships exactly the package files', () => {
  const [info] = JSON.parse(npm(['pack', packageDir, '--json', '--pack-destination', tmp], tmp));
  tarball = path.join(tmp, info.filename);
  assert.deepEqual(info.files.map((f) => f.path).sort(), SHIPPED);
  assert.equal(info.name, 'cdt3d');
});

test('the installed tarball works when imported by name', async () => {
  assert.ok(tarball, 'npm pack failed');
  const project = path.join(tmp, 'project');
  mkdirSync(project);
  writeFileSync(path.join(project, 'package.json'), JSON.stringify({ name: 'cdt3d-user', private: true }));
  npm(['install', '--offline', tarball], project);

  const model = corpusFile('tetrahedron.off');
  const script = `
    import { readFileSync } from 'node:fs';
    import { createCdt3d, Cdt3dError } from 'cdt3d';
    const cdt = await createCdt3d();
    let error = null;
    try { cdt.readPlc(new Uint8Array(0), 'e.stl'); } catch (e) { error = e instanceof Cdt3dError && e.code; }
    const info = cdt.readPlc(readFileSync(${JSON.stringify(path.join(repoRoot, model))}), ${JSON.stringify(model)});
    const mesh = cdt.tetrahedralize(info, { validate: true });
    const { meshInWorker } = await import('cdt3d/worker');
    const inWorker = await meshInWorker(readFileSync(${JSON.stringify(path.join(repoRoot, model))}), {}, { fileName: 'm.off' });
    console.log(JSON.stringify({ info, error, tets: mesh.stats.tets, workerTets: inWorker.stats.tets, threaded: cdt.threaded }));`;
  const r = spawnSync(process.execPath, ['--input-type=module', '-e', script], { cwd: project, encoding: 'utf8' });
  assert.equal(r.status, 0, r.stderr);
  const got = JSON.parse(r.stdout);

  const { createCdt3d } = await importPackage();
  const cdt = await createCdt3d();
  assert.deepEqual(got.info, cdt.readPlc(readFileSync(path.join(repoRoot, model)), model));
  assert.equal(got.error, 'empty');
  assert.equal(got.tets, 1);
  assert.equal(got.workerTets, 1);
  // The installed copy finds its two-thread module (dist/node/, CommonJS by
  // its own package.json inside this ES-module package).
  assert.equal(got.threaded, true);
  // The bin: `npx cdt3d mesh` writes a VTK file and exits 0; bad usage exits 2.
  const vtk = path.join(project, 'out');
  const bin = spawnSync('npx', ['--offline', 'cdt3d', 'mesh', path.join(repoRoot, model), '-o', vtk, '--format', 'vtk', '-q'], { cwd: project, encoding: 'utf8' });
  assert.equal(bin.status, 0, bin.stderr);
  assert.match(readFileSync(`${vtk}.vtk`, 'utf8'), /^# vtk DataFile/);
  const usage = spawnSync('npx', ['--offline', 'cdt3d', 'mesh'], { cwd: project, encoding: 'utf8' });
  assert.equal(usage.status, 2);
  const bad = spawnSync('npx', ['--offline', 'cdt3d', 'mesh', path.join(repoRoot, 'tests/data/open_cube.off'), '--json'], { cwd: project, encoding: 'utf8' });
  assert.equal(bad.status, 1);
  assert.equal(JSON.parse(bad.stdout).error.code, 'open-boundary');
});
