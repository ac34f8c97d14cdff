// wasm/cdt3d.d.ts is hand-written (emscripten 3.1.6 cannot emit it): compile a
// file that uses every declaration with the TypeScript compiler, and check the
// declarations against the running module so the two cannot drift apart.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';
import { before, test } from 'node:test';

import { ERROR_FIELDS, importPackage, INFO_FIELDS, packageFile, repoRoot } from './support.mjs';

const dts = packageFile('cdt3d.d.ts').toString('utf8');

// Member names declared in `interface <name> ... { ... }` (one level of
// braces), each once: an overloaded method (write) has several signatures.
function interfaceMembers(name) {
  const m = new RegExp(`interface ${name}\\b[^{]*\\{([\\s\\S]*?)\\n\\}`).exec(dts);
  assert.ok(m, `interface ${name} in cdt3d.d.ts`);
  const body = m[1].replace(/\/\*\*[\s\S]*?\*\//g, '').replace(/\/\/.*$/gm, '');
  return [...new Set([...body.matchAll(/^\s*(?:readonly\s+)?([A-Za-z_$][\w$]*)\??\s*[:(]/gm)].map((x) => x[1]))];
}

let cdt3d;
let cdt;
before(async () => {
  cdt3d = await importPackage();
  cdt = await cdt3d.createCdt3d();
});

test('tsc --strict accepts tests/js/types-check.mts against cdt3d.d.ts', () => {
  let tsc;
  try {
    const manifest = createRequire(path.join(repoRoot, 'package.json')).resolve('typescript/package.json');
    const bin = JSON.parse(readFileSync(manifest, 'utf8')).bin;
    tsc = path.join(path.dirname(manifest), typeof bin === 'string' ? bin : bin.tsc);
  } catch {
    assert.fail('typescript is not installed: it is a devDependency of the repository root (run npm install).');
  }
  const r = spawnSync(process.execPath, [tsc, '-p', path.join(repoRoot, 'tests', 'js', 'tsconfig.json')], {
    cwd: repoRoot,
    encoding: 'utf8',
  });
  assert.equal(r.status, 0, `tsc failed:\n${r.stdout}${r.stderr}`);
});

test('Cdt3dErrorCode lists exactly the codes of the core', () => {
  const m = /type Cdt3dErrorCode\s*=([^;]*);/.exec(dts);
  assert.ok(m, 'type Cdt3dErrorCode in cdt3d.d.ts');
  const declared = [...m[1].matchAll(/'([^']+)'/g)].map((x) => x[1]);
  assert.deepEqual(declared, [...cdt.errorCodes]);
});

test('interface Cdt3d declares exactly the members of an instance', () => {
  assert.deepEqual(interfaceMembers('Cdt3d').sort(), Object.keys(cdt).sort());
});

test('interface PlcInfo declares exactly the fields readPlc returns, in order', () => {
  assert.deepEqual(interfaceMembers('PlcInfo'), INFO_FIELDS);
});

test('Cdt3dErrorJSON and Cdt3dErrorLocation declare the CLI error fields', () => {
  const fields = [...interfaceMembers('Cdt3dErrorJSON'), ...interfaceMembers('Cdt3dErrorLocation')];
  assert.deepEqual(fields.sort(), [...ERROR_FIELDS].sort());
});

test('interface MemoryUsage matches memoryUsage()', () => {
  assert.deepEqual(interfaceMembers('MemoryUsage').sort(), Object.keys(cdt.memoryUsage()).sort());
});

test('interface MeshStatistics declares exactly the stats tetrahedralize returns', () => {
  const r = cdt.tetrahedralize({ points: [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1], triangles: [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3] });
  assert.deepEqual(interfaceMembers('MeshStatistics').sort(), Object.keys(r.stats).sort());
});

test('interface RepairReport declares exactly the report repair() and tetrahedralize({repair}) return', () => {
  const bytes = readFileSync(path.join(repoRoot, 'tests', 'data', 'tjunction_box.off'));
  const r = cdt.repair({ bytes, fileName: 'tjunction_box.off' });
  assert.deepEqual(interfaceMembers('RepairReport').sort(), Object.keys(r.report).sort());
  assert.deepEqual(interfaceMembers('RepairResult').sort(), Object.keys(r).sort());
  const m = cdt.tetrahedralize({ bytes, fileName: 'tjunction_box.off' }, { repair: true });
  assert.deepEqual(Object.keys(m.repair).sort(), Object.keys(r.report).sort());
});

test('CreateCdt3dOptions declares the options createCdt3d checks', () => {
  assert.deepEqual(interfaceMembers('CreateCdt3dOptions').sort(), ['locateFile', 'threads', 'wasmBinary']);
});

test('the package exports what the declarations export', () => {
  const values = [...dts.matchAll(/^export (?:declare )?(?:class|function|const) ([A-Za-z_$][\w$]*)/gm)].map((x) => x[1]);
  assert.deepEqual(values.sort(), Object.keys(cdt3d).sort());
});
