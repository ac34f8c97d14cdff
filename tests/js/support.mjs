// Shared helpers of the node --test suites on the cdt3d WASM package (not a
// test file itself: node --test only runs *.test.mjs here).
import { spawnSync } from 'node:child_process';
import { existsSync, readdirSync, readFileSync, statSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const repoRoot = fileURLToPath(new URL('../../', import.meta.url));
export const dataDir = path.join(repoRoot, 'tests', 'data');
export const packageDir = path.join(repoRoot, 'wasm');

/** The field names of `cdt3d info --json` on success, in order (without "ok"). */
export const INFO_FIELDS = [
  'file', 'fileVertices', 'points', 'welded', 'unreferenced', 'facets', 'triangles',
  'loops', 'segments', 'holes', 'regions', 'bboxMin', 'bboxMax',
];
/** The field names of the CLI's --json "error" object and of Cdt3dError.toJSON(). */
export const ERROR_FIELDS = [
  'code', 'message', 'file', 'line', 'record', 'facet', 'vertex', 'otherFacet', 'segment',
];

/** Imports the package by its name, as users do (node_modules/cdt3d -> wasm/). */
export async function importPackage() {
  try {
    return await import('cdt3d');
  } catch (e) {
    throw new Error(
      `cannot import the package "cdt3d" (${e.message}).\n` +
        'Build it with `npm run build` (wasm/dist/cdt3d.{js,wasm}) and link it with ' +
        '`npm install` at the repository root (workspaces: ["wasm"]).',
      { cause: e },
    );
  }
}

/** A new instance of the package and its error class: {cdt, Cdt3dError}. */
export async function createInstance() {
  const pkg = await importPackage();
  return { cdt: await pkg.createCdt3d(), Cdt3dError: pkg.Cdt3dError };
}

/** Reads a file of the package folder (wasm/). */
export function packageFile(name) {
  return readFileSync(path.join(packageDir, name));
}

/** Every model file under tests/data, as sorted repo-relative POSIX paths. */
export function corpusFiles() {
  const out = [];
  const walk = (dir) => {
    for (const name of readdirSync(dir)) {
      if (name.startsWith('.')) continue;
      const full = path.join(dir, name);
      if (statSync(full).isDirectory()) walk(full);
      else if (!/^(MANIFEST\.tsv|README(\.md)?|LICEN[CS]E.*)$/i.test(name)) out.push(full);
    }
  };
  if (existsSync(dataDir)) walk(dataDir);
  return out.map((f) => path.relative(repoRoot, f).split(path.sep).join('/')).sort();
}

/** Repo-relative path of the corpus file with this base name (any sub-folder). */
export function corpusFile(baseName) {
  const found = corpusFiles().filter((rel) => path.posix.basename(rel) === baseName);
  if (found.length !== 1) {
    throw new Error(`expected one tests/data file named ${baseName}, found ${found.length}`);
  }
  return found[0];
}

/** tests/data/MANIFEST.tsv as a Map from file (relative to tests/data) to its row object. */
export function readManifest() {
  const file = path.join(dataDir, 'MANIFEST.tsv');
  if (!existsSync(file)) return new Map();
  const lines = readFileSync(file, 'utf8').split('\n').filter((l) => l.trim() !== '');
  const header = lines[0].split('\t');
  const rows = new Map();
  for (const line of lines.slice(1)) {
    const cells = line.split('\t');
    const row = Object.fromEntries(header.map((h, i) => [h, cells[i] ?? '']));
    rows.set(row.file, row);
  }
  return rows;
}

/** True when the native comparisons are switched off explicitly. */
export const skipNative = process.env.CDT3D_SKIP_NATIVE === '1';

/** Path of the native CLI: $CDT3D_NATIVE_CLI or <repo>/.build/native/core/cdt3d. */
export function nativeCliPath() {
  return process.env.CDT3D_NATIVE_CLI || path.join(repoRoot, '.build', 'native', 'core', 'cdt3d');
}

/** Throws a clear error when the native CLI is missing. */
export function requireNativeCli() {
  const cli = nativeCliPath();
  if (!existsSync(cli)) {
    throw new Error(
      `the native CLI ${cli} is missing: build it first (npm run build, or cmake -S . -B .build/native && cmake --build .build/native), ` +
        'point CDT3D_NATIVE_CLI at it, or set CDT3D_SKIP_NATIVE=1 to skip the native comparisons.',
    );
  }
  return cli;
}

/**
 * Runs `cdt3d info <rel> --json` from the repository root and returns its
 * parsed JSON and exit status.
 */
export function nativeInfo(rel) {
  const cli = requireNativeCli();
  const r = spawnSync(cli, ['info', rel, '--json'], {
    cwd: repoRoot,
    encoding: 'utf8',
    maxBuffer: 64 << 20,
  });
  if (r.error) throw r.error;
  let json;
  try {
    json = JSON.parse(r.stdout);
  } catch (e) {
    throw new Error(
      `\`${cli} info ${rel} --json\` did not print JSON (exit ${r.status}, signal ${r.signal}):\n` +
        `stdout: ${r.stdout.slice(0, 2000)}\nstderr: ${r.stderr.slice(0, 2000)}`,
      { cause: e },
    );
  }
  return { json, status: r.status, stderr: r.stderr };
}

/** Small deterministic PRNG (xorshift32) for the mutation tests. */
export function prng(seed) {
  let s = seed >>> 0 || 1;
  return () => {
    s ^= s << 13;
    s >>>= 0;
    s ^= s >>> 17;
    s ^= s << 5;
    s >>>= 0;
    return s / 0x100000000;
  };
}
