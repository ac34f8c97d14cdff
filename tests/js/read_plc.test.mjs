// readPlc on the test corpus: the WASM package must give exactly what the
// native CLI `cdt3d info MODEL --json` prints, for every file in tests/data;
// errors must carry the expected code and never break the module.
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  corpusFile,
  corpusFiles,
  ERROR_FIELDS,
  importPackage,
  INFO_FIELDS,
  nativeInfo,
  prng,
  readManifest,
  repoRoot,
  requireNativeCli,
  skipNative,
} from './support.mjs';

const files = corpusFiles();
const manifest = readManifest();

// Manifest "expected" values that are reader errors, with their error code.
// The other invalid-* kinds (open, selfintersect, nonmanifold) are legal PLCs
// as far as reading goes; the mesher reports them.
const READER_ERRORS = {
  'invalid-empty': 'empty',
  'invalid-truncated': 'truncated',
  'invalid-nan': 'nan',
  'invalid-degenerate': 'degenerate',
  'invalid-duplicate': 'duplicate',
  'invalid-nonplanar': 'nonplanar',
};

let cdt3d;
let cdt;
const bytesOf = (rel) => readFileSync(path.join(repoRoot, rel));

// Returns {ok: true, info} or {ok: false, error} from the WASM package; any
// throw that is not a Cdt3dError fails the test.
function wasmRead(rel, bytes = bytesOf(rel)) {
  try {
    return { ok: true, info: cdt.readPlc(bytes, rel) };
  } catch (e) {
    assert.ok(e instanceof cdt3d.Cdt3dError, `${rel}: threw a non-Cdt3dError: ${e?.stack ?? e}`);
    return { ok: false, error: e };
  }
}

// A tiny valid model read after every error: the module must still work.
const probe = corpusFile('tetrahedron.off');
function assertStillWorks() {
  const r = wasmRead(probe);
  assert.ok(r.ok, `the module stopped working after an error: ${r.error?.message}`);
  assert.equal(r.info.points, 4);
}

before(async () => {
  cdt3d = await importPackage();
  cdt = await cdt3d.createCdt3d();
});

test('the corpus is present in tests/data', () => {
  assert.ok(files.length > 0, `no model files under ${path.join(repoRoot, 'tests/data')}`);
  assert.ok(files.includes(probe), `${probe} is missing`);
});

describe('WASM readPlc equals native `cdt3d info --json`, field for field', () => {
  test('the native CLI is built', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
    requireNativeCli();
  });

  for (const rel of files) {
    test(rel, { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
      const native = nativeInfo(rel);
      const { json } = native;
      const wasm = wasmRead(rel);
      if (json.ok === true) {
        assert.equal(native.status, 0, `native exit status ${native.status} with ok:true`);
        assert.deepEqual(Object.keys(json), ['ok', ...INFO_FIELDS], 'native JSON field names');
        assert.ok(wasm.ok, `native read it, WASM threw ${wasm.error?.code}: ${wasm.error?.message}`);
        const { ok, ...expected } = json;
        assert.deepEqual(Object.keys(wasm.info), INFO_FIELDS, 'WASM field names');
        assert.deepEqual(wasm.info, expected);
      } else {
        assert.equal(json.ok, false, 'native JSON has ok:true or ok:false');
        assert.notEqual(native.status, 0, 'native exit status with ok:false');
        assert.deepEqual(Object.keys(json.error), ERROR_FIELDS, 'native error field names');
        assert.ok(!wasm.ok, `native failed with ${json.error.code}, WASM read it`);
        assert.deepEqual(wasm.error.toJSON(), json.error);
        for (const f of ERROR_FIELDS) assert.equal(wasm.error[f], json.error[f], f);
        assertStillWorks();
      }
    });
  }
});

describe('MANIFEST.tsv expectations', () => {
  for (const rel of files) {
    const row = manifest.get(rel.replace(/^tests\/data\//, ''));
    if (!row) continue;
    const code = READER_ERRORS[row.expected];
    if (code) {
      test(`${rel}: ${row.expected} -> Cdt3dError "${code}"`, () => {
        const r = wasmRead(rel);
        assert.ok(!r.ok, 'readPlc succeeded');
        assert.equal(r.error.code, code, r.error.message);
        assert.equal(r.error.file, rel);
        assertStillWorks();
      });
    } else {
      test(`${rel}: ${row.expected} reads; counts match the manifest`, () => {
        const r = wasmRead(rel);
        assert.ok(r.ok, `${r.error?.code}: ${r.error?.message}`);
        // MANIFEST: STL "vertices" are distinct points; other formats count records.
        const vertices = row.format.startsWith('stl') ? r.info.points : r.info.fileVertices;
        assert.equal(vertices, Number(row.vertices), 'vertices');
        assert.equal(r.info.triangles, Number(row.triangles), 'triangles');
      });
    }
  }
});

describe('damaged inputs never break the module', () => {
  // Every prefix (and random byte changes) of the small files: each read either
  // succeeds or throws a Cdt3dError with a reader code, never "internal" and
  // never an abort; the module keeps working throughout.
  const small = files.filter((rel) => bytesOf(rel).length <= 4096);

  test('every prefix of every small file', () => {
    let errors = 0;
    for (const rel of small) {
      const bytes = bytesOf(rel);
      for (let n = 0; n < bytes.length; n++) {
        const r = wasmRead(rel, bytes.subarray(0, n));
        if (!r.ok) {
          errors++;
          assert.notEqual(r.error.code, 'internal', `${rel}[0:${n}]: ${r.error.message}`);
          assert.equal(r.error.file, rel);
        }
      }
    }
    assert.ok(errors > 0);
    assertStillWorks();
  });

  test('random byte changes in every small file', () => {
    const rand = prng(20240521);
    const alphabet = Buffer.from('0123456789-+.eE \n\t#/,nanINFxyz\0\xff');
    for (const rel of small) {
      const bytes = bytesOf(rel);
      if (bytes.length === 0) continue;
      for (let k = 0; k < 200; k++) {
        const mutated = Buffer.from(bytes);
        const changes = 1 + Math.floor(rand() * 4);
        for (let c = 0; c < changes; c++) {
          const at = Math.floor(rand() * mutated.length);
          mutated[at] = rand() < 0.5 ? alphabet[Math.floor(rand() * alphabet.length)] : Math.floor(rand() * 256);
        }
        const r = wasmRead(rel, mutated);
        if (!r.ok) assert.notEqual(r.error.code, 'internal', `${rel} mutation ${k}: ${r.error.message}`);
      }
    }
    assertStillWorks();
  });
});

describe('damaged inputs: WASM equals native too', () => {
  // A sample of prefixes and byte changes of the small files, written to a
  // temporary folder under their own names (the extension picks the reader).
  const tmp = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-damaged-'));
  after(() => rmSync(tmp, { recursive: true, force: true }));
  const small = files.filter((rel) => bytesOf(rel).length <= 4096);

  for (const rel of small) {
    test(rel, { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
      const bytes = bytesOf(rel);
      const rand = prng(bytes.length * 7919 + 1);
      const variants = [];
      for (let i = 1; i <= 8; i++) variants.push(bytes.subarray(0, Math.floor((bytes.length * i) / 9)));
      for (let i = 0; i < 8 && bytes.length > 0; i++) {
        const m = Buffer.from(bytes);
        m[Math.floor(rand() * m.length)] = Math.floor(rand() * 256);
        m[Math.floor(rand() * m.length)] = '0-.eEn \n'.charCodeAt(Math.floor(rand() * 8));
        variants.push(m);
      }
      variants.forEach((v, i) => {
        const dir = path.join(tmp, path.dirname(rel), String(i));
        mkdirSync(dir, { recursive: true });
        const file = path.join(dir, path.basename(rel));
        writeFileSync(file, v);
        const { json } = nativeInfo(file);
        const wasm = wasmRead(file, v);
        if (json.ok) {
          assert.ok(wasm.ok, `${file}: native read it, WASM threw ${wasm.error?.code}: ${wasm.error?.message}`);
          const { ok, ...expected } = json;
          assert.deepEqual(wasm.info, expected, file);
        } else {
          assert.ok(!wasm.ok, `${file}: native failed with ${json.error.code}, WASM read it`);
          assert.deepEqual(wasm.error.toJSON(), json.error, file);
        }
      });
    });
  }
});
