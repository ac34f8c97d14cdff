// The package's browser entry ("default" export condition) in a real browser:
// headless Chromium loads it on a page and in a module worker, reads the small
// corpus files, meshes one model and posts the results back; they must equal
// Node's. Served with the COOP/COEP headers (cross-origin isolated: the
// two-thread module), without them (the single-threaded fallback), and with
// them but without the thread pool's worker script (the fallback again).
// Needs /usr/bin/chromium (or $CHROMIUM_PATH); CDT3D_SKIP_BROWSER=1 skips.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, statSync } from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { corpusFiles, importPackage, packageDir, packageFile, repoRoot } from './support.mjs';

const skip = process.env.CDT3D_SKIP_BROWSER === '1' && 'CDT3D_SKIP_BROWSER=1';
const chromiumPath = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
const files = corpusFiles().filter((rel) => statSync(path.join(repoRoot, rel)).size <= 512 * 1024);
// Meshed on both modules: enough segments to recover that the second thread has work.
const MESHED = 'tests/data/bunny.off';

const MIME = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.wasm': 'application/wasm',
  '.json': 'application/json',
};

// Runs the files through one cdt3d instance; shared by the page and the worker.
const RUN = `
async function run(createCdt3d, Cdt3dError, files) {
  const t0 = performance.now();
  const cdt = await createCdt3d();
  const out = { createMs: performance.now() - t0, version: cdt.version, threaded: cdt.threaded, isolated: self.crossOriginIsolated === true, results: {} };
  for (const rel of files) {
    const bytes = new Uint8Array(await (await fetch('/' + rel)).arrayBuffer());
    try {
      out.results[rel] = { ok: true, info: cdt.readPlc(bytes, rel) };
    } catch (e) {
      out.results[rel] = e instanceof Cdt3dError
        ? { ok: false, error: e.toJSON() }
        : { ok: false, unexpected: String(e && e.stack || e) };
    }
  }
  const bytes = new Uint8Array(await (await fetch('/${MESHED}')).arrayBuffer());
  const mesh = cdt.tetrahedralize({ bytes, fileName: '${MESHED}' }, { validate: true });
  out.mesh = {
    stats: Object.fromEntries(Object.entries(mesh.stats).filter(([k]) => !/^ms[A-Z]/.test(k))),
    validation: mesh.validation,
    tets: Array.from(mesh.tets.slice(0, 400)),
    tetCount: mesh.tets.length,
  };
  return out;
}`;

function page(entry) {
  return `<!doctype html><meta charset="utf-8"><title>cdt3d package test</title>
<script type="module">
${RUN}
const report = (body) => fetch('/result', { method: 'POST', body: JSON.stringify(body) });
try {
  const files = await (await fetch('/files.json')).json();
  const { createCdt3d, Cdt3dError } = await import(${JSON.stringify(entry)});
  const main = await run(createCdt3d, Cdt3dError, files);
  const worker = new Worker('/worker.js', { type: 'module' });
  const inWorker = await new Promise((resolve, reject) => {
    worker.onmessage = (e) => resolve(e.data);
    worker.onerror = (e) => reject(new Error('worker error: ' + (e.message || 'failed to load')));
    worker.postMessage(files);
  });
  await report({ main, worker: inWorker });
} catch (e) {
  await report({ failed: String(e && e.stack || e) });
}
</script>`;
}

function worker(entry) {
  return `import { createCdt3d, Cdt3dError } from ${JSON.stringify(entry)};
${RUN}
self.onmessage = async (e) => {
  try {
    self.postMessage(await run(createCdt3d, Cdt3dError, e.data));
  } catch (err) {
    self.postMessage({ failed: String(err && err.stack || err) });
  }
};`;
}

let server;
let origin;
let resultPromise;
let deliver;
let isolated = false; // send the COOP/COEP headers
let noPoolWorker = false; // answer 404 for the two-thread module's worker script

before(async () => {
  if (skip) return;
  const pkg = JSON.parse(packageFile('package.json'));
  const entry = '/pkg/' + pkg.exports['.'].default.replace(/^\.\//, '');
  server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://x');
    const send = (status, type, body) => {
      const headers = { 'content-type': type, 'cache-control': 'no-store' };
      if (isolated) {
        headers['cross-origin-opener-policy'] = 'same-origin';
        headers['cross-origin-embedder-policy'] = 'require-corp';
      }
      res.writeHead(status, headers);
      res.end(body);
    };
    if (req.method === 'POST' && url.pathname === '/result') {
      let body = '';
      req.on('data', (c) => (body += c));
      req.on('end', () => {
        send(204, 'text/plain', '');
        deliver(JSON.parse(body));
      });
      return;
    }
    if (noPoolWorker && url.pathname.endsWith('/threads/cdt3d.worker.js')) return send(404, 'text/plain', 'not found');
    if (url.pathname === '/') return send(200, MIME['.html'], page(entry));
    if (url.pathname === '/worker.js') return send(200, MIME['.js'], worker(entry));
    if (url.pathname === '/files.json') return send(200, MIME['.json'], JSON.stringify(files));
    // /pkg/* from the package folder; /tests/data/* from the corpus.
    const rel = decodeURIComponent(url.pathname);
    let file = null;
    if (rel.startsWith('/pkg/')) file = path.join(packageDir, rel.slice(5));
    else if (rel.startsWith('/tests/data/')) file = path.join(repoRoot, rel.slice(1));
    const inside = file && (file.startsWith(packageDir + path.sep) || file.startsWith(path.join(repoRoot, 'tests', 'data') + path.sep));
    if (!inside || !existsSync(file) || !statSync(file).isFile()) return send(404, 'text/plain', 'not found');
    send(200, MIME[path.extname(file)] ?? 'application/octet-stream', readFileSync(file));
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  origin = `http://127.0.0.1:${server.address().port}`;
});

after(() => server?.close());

for (const withHeaders of [true, false]) {
  const which = withHeaders ? 'cross-origin isolated: two threads' : 'not isolated: one thread';
  test(`the browser entry works on a page and in a module worker, ${which} (headless Chromium)`, { skip, timeout: 180_000 }, () =>
    runInChromium(withHeaders),
  );
}

test('isolated, but the thread pool cannot load: the single-threaded module, without waiting for the time-out', { skip, timeout: 180_000 }, async () => {
  noPoolWorker = true;
  try {
    const t0 = Date.now();
    await runInChromium(true, false);
    // Page and worker each fall back; the 10 s time-out would have taken 20 s.
    assert.ok(Date.now() - t0 < 90_000);
  } finally {
    noPoolWorker = false;
  }
});

async function runInChromium(withHeaders, threads = withHeaders) {
  isolated = withHeaders;
  resultPromise = new Promise((resolve) => {
    deliver = resolve;
  });
  assert.ok(
    existsSync(chromiumPath),
    `Chromium not found at ${chromiumPath}: apt-get install chromium, set CHROMIUM_PATH, or CDT3D_SKIP_BROWSER=1 to skip.`,
  );
  assert.ok(files.length > 0, 'no small corpus files in tests/data');
  const profile = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-chromium-'));
  const browser = spawn(
    chromiumPath,
    [
      '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      `--user-data-dir=${profile}`, `${origin}/`,
    ],
    { stdio: ['ignore', 'ignore', 'pipe'], detached: true },
  );
  let stderr = '';
  browser.stderr.on('data', (c) => (stderr = (stderr + c).slice(-4000)));
  const exited = new Promise((resolve) => browser.on('exit', (code) => resolve({ exitedEarly: code })));
  let timer;
  const timeout = new Promise((resolve) => {
    timer = setTimeout(() => resolve({ timedOut: true }), 90_000);
  });
  let got;
  try {
    got = await Promise.race([resultPromise, exited, timeout]);
  } finally {
    clearTimeout(timer);
    if (browser.exitCode === null) {
      try {
        process.kill(-browser.pid, 'SIGTERM'); // the process group started above
      } catch {}
    }
    await Promise.race([exited, new Promise((r) => setTimeout(r, 5000).unref())]);
    rmSync(profile, { recursive: true, force: true });
  }
  assert.ok(!got.timedOut, `no result from the page within 90 s; Chromium stderr:\n${stderr}`);
  assert.ok(!('exitedEarly' in got), `Chromium exited (${got.exitedEarly}) before reporting:\n${stderr}`);
  assert.equal(got.failed, undefined, `the page failed: ${got.failed}`);

  // The same files through the Node entry.
  const { createCdt3d, Cdt3dError } = await importPackage();
  const cdt = await createCdt3d();
  const expected = {};
  for (const rel of files) {
    try {
      expected[rel] = { ok: true, info: cdt.readPlc(readFileSync(path.join(repoRoot, rel)), rel) };
    } catch (e) {
      assert.ok(e instanceof Cdt3dError, String(e));
      expected[rel] = { ok: false, error: e.toJSON() };
    }
  }
  const mesh = cdt.tetrahedralize({ bytes: readFileSync(path.join(repoRoot, MESHED)), fileName: MESHED }, { validate: true });
  const stats = Object.fromEntries(Object.entries(mesh.stats).filter(([k]) => !/^ms[A-Z]/.test(k)));
  for (const where of ['main', 'worker']) {
    assert.equal(got[where].failed, undefined, `${where}: ${got[where].failed}`);
    assert.equal(got[where].version, cdt.version, `${where}: version`);
    assert.equal(got[where].isolated, withHeaders, `${where}: crossOriginIsolated`);
    assert.equal(got[where].threaded, threads, `${where}: the ${threads ? 'two-thread' : 'single-threaded'} module`);
    if (!threads) assert.ok(got[where].createMs < 9_000, `${where}: ${got[where].createMs} ms to start`);
    assert.deepEqual(got[where].results, expected, `${where}: results differ from Node`);
    assert.deepEqual(got[where].mesh.stats, stats, `${where}: mesh statistics differ from Node`);
    assert.deepEqual(got[where].mesh.validation, mesh.validation, `${where}: validation`);
    assert.equal(got[where].mesh.tetCount, mesh.tets.length, `${where}: tets`);
    assert.deepEqual(got[where].mesh.tets, Array.from(mesh.tets.slice(0, 400)), `${where}: the first tets`);
  }
}
