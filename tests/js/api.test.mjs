// The public JS API of the cdt3d package: exports, arguments, errors, instances
// and memory. Corpus results are checked against native in read_plc.test.mjs.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { before, describe, test } from 'node:test';
import { pathToFileURL } from 'node:url';

import { corpusFile, ERROR_FIELDS, importPackage, INFO_FIELDS, packageDir, packageFile, repoRoot } from './support.mjs';

const model = corpusFile('cube_ascii.stl');
const modelBytes = () => readFileSync(path.join(repoRoot, model));

let cdt3d;
let cdt;
before(async () => {
  cdt3d = await importPackage();
  cdt = await cdt3d.createCdt3d();
});

function assertCdt3dError(fn, code, what) {
  let thrown;
  try {
    fn();
  } catch (e) {
    thrown = e;
  }
  assert.ok(thrown !== undefined, `${what}: did not throw`);
  assert.ok(thrown instanceof cdt3d.Cdt3dError, `${what}: threw ${thrown?.stack ?? thrown}`);
  assert.ok(thrown instanceof Error);
  assert.equal(thrown.name, 'Cdt3dError');
  assert.equal(thrown.code, code, `${what}: ${thrown.message}`);
  assert.ok(thrown.message.length > 0);
  return thrown;
}

describe('package', () => {
  test('exports exactly createCdt3d and Cdt3dError', () => {
    assert.deepEqual(Object.keys(cdt3d).sort(), ['Cdt3dError', 'createCdt3d']);
    assert.equal(typeof cdt3d.createCdt3d, 'function');
    assert.equal(typeof cdt3d.Cdt3dError, 'function');
  });

  test('the "node" condition resolves to node.js, "default" to index.js', () => {
    const pkg = JSON.parse(packageFile('package.json'));
    assert.equal(pkg.name, 'cdt3d');
    assert.equal(pkg.type, 'module');
    assert.deepEqual(Object.keys(pkg.exports['.']), ['types', 'node', 'default']);
    assert.equal(import.meta.resolve('cdt3d'), pathToFileURL(path.join(packageDir, pkg.exports['.'].node)).href);
  });

  test('version matches wasm/package.json and the CMake project version', () => {
    const pkg = JSON.parse(packageFile('package.json'));
    const cmake = readFileSync(path.join(repoRoot, 'CMakeLists.txt'), 'utf8');
    const m = /project\(\s*cdt3d\s+VERSION\s+([0-9.]+)/.exec(cmake);
    assert.ok(m, 'project(cdt3d VERSION ...) in CMakeLists.txt');
    assert.equal(cdt.version, pkg.version);
    assert.equal(cdt.version, m[1]);
  });

  test('errorCodes lists the core codes, frozen', () => {
    assert.ok(Object.isFrozen(cdt.errorCodes));
    for (const c of ['io', 'empty', 'truncated', 'parse', 'nan', 'invalid-argument', 'out-of-memory', 'internal']) {
      assert.ok(cdt.errorCodes.includes(c), c);
    }
    assert.ok(!cdt.errorCodes.includes('ok'));
    assert.equal(new Set(cdt.errorCodes).size, cdt.errorCodes.length);
  });

  test('the instance is frozen and has the documented members', () => {
    assert.ok(Object.isFrozen(cdt));
    assert.deepEqual(Object.keys(cdt).sort(), ['delaunay', 'errorCodes', 'memoryUsage', 'readPlc', 'readSurface', 'repair', 'tetrahedralize', 'threaded', 'validate', 'version', 'write']);
  });
});

describe('readPlc arguments', () => {
  test('Buffer, Uint8Array, ArrayBuffer, views with an offset and SharedArrayBuffer give one result', () => {
    const buf = modelBytes();
    const expected = cdt.readPlc(buf, model);
    assert.deepEqual(Object.keys(expected), INFO_FIELDS);
    assert.equal(expected.file, model);

    const copy = new Uint8Array(buf);
    assert.deepEqual(cdt.readPlc(copy, model), expected);
    assert.deepEqual(cdt.readPlc(copy.buffer, model), expected);

    // The bytes in the middle of a larger buffer, with garbage around them.
    const big = new Uint8Array(buf.length + 64).fill(0x5a);
    big.set(buf, 32);
    const middle = big.subarray(32, 32 + buf.length);
    assert.deepEqual(cdt.readPlc(middle, model), expected);
    assert.deepEqual(cdt.readPlc(new DataView(big.buffer, 32, buf.length), model), expected);
    assert.deepEqual(cdt.readPlc(new Int8Array(big.buffer, 32, buf.length), model), expected);

    const shared = new SharedArrayBuffer(buf.length);
    new Uint8Array(shared).set(buf);
    assert.deepEqual(cdt.readPlc(shared, model), expected);
    assert.deepEqual(cdt.readPlc(new Uint8Array(shared), model), expected);
  });

  test('the input is not modified and results are plain data', () => {
    const buf = modelBytes();
    const before = Buffer.from(buf);
    const info = cdt.readPlc(buf, model);
    assert.deepEqual(buf, before);
    assert.deepEqual(JSON.parse(JSON.stringify(info)), info);
    assert.ok(Array.isArray(info.bboxMin) && info.bboxMin.length === 3);
    assert.ok(Array.isArray(info.bboxMax) && info.bboxMax.length === 3);
    assert.deepEqual(structuredClone(info), info);
  });

  const bad = [
    ['undefined bytes', undefined, model],
    ['null bytes', null, model],
    ['a string', 'solid cube', model],
    ['a number', 42, model],
    ['a plain array', [1, 2, 3], model],
    ['a plain object', { length: 3 }, model],
    ['a Blob-like object', { arrayBuffer() {} }, model],
    ['a missing file name', new Uint8Array(4), undefined],
    ['an empty file name', new Uint8Array(4), ''],
    ['a numeric file name', new Uint8Array(4), 7],
    ['a String object', new Uint8Array(4), new String('a.off')],
    ['null file name', new Uint8Array(4), null],
  ];
  for (const [what, bytes, name] of bad) {
    test(`${what} -> Cdt3dError "invalid-argument"`, () => {
      const e = assertCdt3dError(() => cdt.readPlc(bytes, name), 'invalid-argument', what);
      for (const f of ['line', 'record', 'facet', 'vertex', 'otherFacet', 'segment']) assert.equal(e[f], -1, f);
      assert.equal(e.file, typeof name === 'string' ? name : '');
      assert.equal(cdt.readPlc(modelBytes(), model).points, 8, 'still works afterwards');
    });
  }

  test('no arguments at all -> "invalid-argument"', () => {
    assertCdt3dError(() => cdt.readPlc(), 'invalid-argument', 'readPlc()');
  });

  test('a detached ArrayBuffer -> "invalid-argument"', () => {
    const ab = new ArrayBuffer(16);
    structuredClone(ab, { transfer: [ab] });
    assertCdt3dError(() => cdt.readPlc(ab, model), 'invalid-argument', 'detached');
  });

  test('an empty file -> "empty" with the file name', () => {
    const e = assertCdt3dError(() => cdt.readPlc(new Uint8Array(0), 'none.off'), 'empty', 'empty');
    assert.equal(e.file, 'none.off');
  });
});

describe('Cdt3dError', () => {
  test('constructor fills missing locations with -1', () => {
    const e = new cdt3d.Cdt3dError('parse', 'Bad token.', { file: 'a.off', line: 3 });
    assert.ok(e instanceof Error);
    assert.equal(e.name, 'Cdt3dError');
    assert.equal(String(e), 'Cdt3dError: Bad token.');
    assert.deepEqual(e.toJSON(), {
      code: 'parse', message: 'Bad token.', file: 'a.off', line: 3, record: -1, facet: -1, vertex: -1, otherFacet: -1, segment: -1,
    });
    assert.ok(e.stack.includes('Bad token.'));
  });

  test('toJSON has the CLI error fields and survives postMessage-style cloning', () => {
    let err;
    try {
      cdt.readPlc(new Uint8Array(0), 'x.stl');
    } catch (e) {
      err = e;
    }
    const json = err.toJSON();
    assert.deepEqual(Object.keys(json), ERROR_FIELDS);
    const cloned = structuredClone(json);
    const rebuilt = new cdt3d.Cdt3dError(cloned.code, cloned.message, cloned);
    assert.deepEqual(rebuilt.toJSON(), json);
    assert.deepEqual(JSON.parse(JSON.stringify(err)), json);
  });

  test('a cause is kept', () => {
    const cause = new Error('inner');
    assert.equal(new cdt3d.Cdt3dError('internal', 'outer', { cause }).cause, cause);
  });
});

describe('instances', () => {
  test('createCdt3d makes independent instances', async () => {
    const [a, b] = await Promise.all([cdt3d.createCdt3d(), cdt3d.createCdt3d()]);
    assert.notEqual(a, b);
    assert.throws(() => a.readPlc(new Uint8Array(0), 'x.off'), cdt3d.Cdt3dError);
    assert.deepEqual(b.readPlc(modelBytes(), model), a.readPlc(modelBytes(), model));
  });

  test('bad options reject with "invalid-argument"', async () => {
    for (const options of [5, 'x', { wasmBinary: 'abc' }, { wasmBinary: [0, 97, 115, 109] }, { locateFile: 'x' }]) {
      await assert.rejects(cdt3d.createCdt3d(options), (e) => {
        assert.ok(e instanceof cdt3d.Cdt3dError, String(e));
        assert.equal(e.code, 'invalid-argument');
        return true;
      });
    }
  });

  test('a corrupt wasmBinary rejects with a Cdt3dError', async () => {
    const corrupt = new Uint8Array([0, 97, 115, 109, 9, 9, 9, 9]);
    await assert.rejects(cdt3d.createCdt3d({ wasmBinary: corrupt }), (e) => {
      assert.ok(e instanceof cdt3d.Cdt3dError, String(e));
      assert.equal(e.code, 'internal');
      assert.match(e.message, /CompileError/);
      assert.doesNotMatch(e.message, /ASSERTIONS/);
      return true;
    });
  });

  test('the browser/worker entry (index.js) works in Node given wasmBinary', async () => {
    const pkg = JSON.parse(packageFile('package.json'));
    const browser = await import(pathToFileURL(path.join(packageDir, pkg.exports['.'].default)).href);
    assert.deepEqual(Object.keys(browser).sort(), ['Cdt3dError', 'createCdt3d']);
    const b = await browser.createCdt3d({ wasmBinary: packageFile('dist/cdt3d.wasm') });
    assert.deepEqual(b.readPlc(modelBytes(), model), cdt.readPlc(modelBytes(), model));
    // Both entries share api.js, so one Cdt3dError class serves both.
    assert.equal(browser.Cdt3dError, cdt3d.Cdt3dError);
  });
});

describe('memory', () => {
  test('repeated reads and errors do not leak', () => {
    const biggest = corpusFile('grid_10x10x10_boundary.off');
    const bytes = readFileSync(path.join(repoRoot, biggest));
    const round = () => {
      cdt.readPlc(bytes, biggest);
      assert.throws(() => cdt.readPlc(bytes.subarray(0, bytes.length >> 1), biggest), cdt3d.Cdt3dError);
      assert.throws(() => cdt.readPlc(new Uint8Array(0), 'e.stl'), cdt3d.Cdt3dError);
    };
    round();
    const base = cdt.memoryUsage();
    assert.ok(base.heapBytes >= 16 << 20, `heapBytes ${base.heapBytes}`);
    for (let i = 0; i < 50; i++) round();
    const after = cdt.memoryUsage();
    assert.equal(after.allocatedBytes, base.allocatedBytes, 'allocated bytes after 50 rounds');
    assert.equal(after.heapBytes, base.heapBytes, 'the heap did not grow');
  });
});
