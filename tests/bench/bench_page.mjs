// Browser bench: the classic models through the demo page in headless
// Chromium against the native CLI, in the same run, printed as ratios of the
// core's own clock (`msTotal`: reading to carving, without validation).
// A bench, not a test: it asserts nothing and its numbers depend on the load.
//
//   node tests/bench/bench_page.mjs [MODEL ...]
//
// MODEL is a path, or a file name looked up in $CDT3D_BENCH_MODELS, tests/data
// and web/public/samples (default: bunny.off armadillo.obj nefertiti.obj; the
// last is not in the repository: point CDT3D_BENCH_MODELS at a folder with it).
// For each model, BENCH_FIRST times (default 1): a fresh load of the page
// (no HTTP cache, no default sample) that waits until the page says its
// mesher is ready, opens the model through the file input ("first"), and
// opens it again BENCH_LATER times (default 3: "later"); right before each
// of these page runs the native CLI meshes the model once
// (`cdt3d mesh MODEL --validate --json`), so that both see the same load.
// Medians of each. The page is served with the
// COOP/COEP headers (the two-thread module); BENCH_ISOLATION=0 serves it
// without them (the single-threaded fallback). Needs the native and WASM
// builds (tests/scripts/build.sh) and /usr/bin/chromium (or $CHROMIUM_PATH).
import { execFileSync } from 'node:child_process';
import { existsSync, statSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { chromiumPath, recordLongTasks, withServedPage } from '../js/page-support.mjs';

const repoRoot = fileURLToPath(new URL('../../', import.meta.url));
const nativeCli = path.join(repoRoot, '.build', 'native', 'core', 'cdt3d');
const isolation = process.env.BENCH_ISOLATION !== '0';
const laterRuns = positive('BENCH_LATER', 3);
const firstRuns = positive('BENCH_FIRST', 1);
const DEFAULT_MODELS = ['bunny.off', 'armadillo.obj', 'nefertiti.obj'];

function positive(name, fallback) {
  const text = process.env[name];
  if (text === undefined || text === '') return fallback;
  const n = Number(text);
  if (!Number.isInteger(n) || n < 1) fail(`${name} must be a positive integer, got "${text}".`);
  return n;
}

function fail(message) {
  console.error(`bench_page: ${message}`);
  process.exit(2);
}

function findModel(name) {
  if (existsSync(name) && statSync(name).isFile()) return path.resolve(name);
  const dirs = [process.env.CDT3D_BENCH_MODELS, path.join(repoRoot, 'tests', 'data'),
    path.join(repoRoot, 'web', 'public', 'samples')].filter(Boolean);
  for (const dir of dirs) {
    const file = path.join(dir, name);
    if (existsSync(file)) return file;
  }
  fail(`model ${name} not found (looked in ${dirs.join(', ')}); pass a path or set CDT3D_BENCH_MODELS.`);
}

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};

function native(file) {
  const out = execFileSync(nativeCli, ['mesh', file, '--validate', '--json', '-q'], {
    encoding: 'utf8',
    maxBuffer: 64 << 20,
  });
  const stats = JSON.parse(out);
  if (!stats.ok) fail(`the native CLI failed on ${file}: ${out.slice(0, 300)}`);
  return stats;
}

// Opens `file` through the page's file input; resolves to what the page measured.
async function openOnPage(page, file) {
  const before = await page.evaluate(() => window.cdt3dDemo.timings.length);
  await page.setInputFiles('#file', file);
  await page.waitForFunction((n) => window.cdt3dDemo.timings.length > n, before);
  await page.waitForFunction(() => ['done', 'error', 'cancelled'].includes(document.body.dataset.state), null, {
    timeout: 600_000,
    polling: 50,
  });
  return page.evaluate(() => {
    const demo = window.cdt3dDemo;
    const t = demo.timings.at(-1);
    const long = window.__longTasks.filter((task) => task.start + task.duration > t.start);
    return {
      state: document.body.dataset.state,
      error: demo.error?.message ?? null,
      ms: demo.stats?.msTotal ?? NaN,
      tets: demo.stats?.tets ?? 0,
      wall: t.meshEnd - t.meshStart,
      shown: t.shown - t.start,
      longest: Math.max(0, ...long.map((task) => task.duration)),
    };
  });
}

async function main() {
  const names = process.argv.slice(2).length > 0 ? process.argv.slice(2) : DEFAULT_MODELS;
  const models = names.map(findModel);
  if (!existsSync(nativeCli)) fail(`${nativeCli} is missing: bash tests/scripts/build.sh`);
  if (!existsSync(path.join(repoRoot, 'wasm', 'dist', 'cdt3d.wasm'))) fail('wasm/dist is missing: bash tests/scripts/build.sh');
  if (!existsSync(chromiumPath)) fail(`Chromium not found at ${chromiumPath} (set CHROMIUM_PATH).`);

  await withServedPage({ isolated: isolation }, async (context, origin) => {
    await context.addInitScript(recordLongTasks);

    console.log(`# ${new Date().toISOString()} load ${os.loadavg().map((l) => l.toFixed(2)).join(' ')}; ` +
      `page ${isolation ? 'cross-origin isolated' : 'not isolated'}; ${firstRuns} page load(s) per model, ${laterRuns} later runs each`);
    const rows = [];
    for (const file of models) {
      const name = path.basename(file);
      const nat = [];
      const firsts = [];
      const later = [];
      let engine;
      let readyMs;
      for (let k = 0; k < firstRuns; k++) {
        for (const p of context.pages()) await p.close();
        const page = await context.newPage();
        const t0 = Date.now();
        await page.goto(`${origin}/?model=`);
        await page.waitForFunction(() => ['ready', 'failed'].includes(document.body.dataset.engine), null, {
          timeout: 300_000,
        });
        engine = await page.evaluate(() => window.cdt3dDemo.engine);
        readyMs = Date.now() - t0;
        nat.push(native(file));
        const first = await openOnPage(page, file);
        if (first.state !== 'done') fail(`${name}: the page ended in "${first.state}": ${first.error}`);
        firsts.push(first);
        for (let i = 0; i < laterRuns; i++) {
          nat.push(native(file));
          later.push(await openOnPage(page, file));
        }
      }
      const first = firsts[0];
      rows.push({
        name, tets: nat[0].tets, native: median(nat.map((n) => n.msTotal)), first: median(firsts.map((f) => f.ms)),
        later: median(later.map((r) => r.ms)), threads: engine.threaded ? 2 : 1, readyMs, warm: engine.runs,
        longest: Math.max(...firsts.map((f) => f.longest), ...later.map((r) => r.longest)),
      });
      const r = rows.at(-1);
      console.log(
        `${name}: ${r.tets} tets; native ${nat.map((x) => x.msTotal.toFixed(0)).join('/')} ms; ` +
          `page ready after ${readyMs} ms (${r.threads} thread${r.threads === 1 ? '' : 's'}, warm-up rounds ` +
          `${r.warm.map((x) => x.toFixed(0)).join('/')} ms); first ${firsts.map((f) => f.ms.toFixed(0)).join('/')} ms ` +
          `(worker ${first.wall.toFixed(0)} ms, shown after ${first.shown.toFixed(0)} ms); later ` +
          `${later.map((x) => x.ms.toFixed(0)).join('/')} ms; longest main-thread task ${r.longest.toFixed(0)} ms`,
      );
    }
    console.log('\n| model | tets | native ms | page first ms | first / native | page later ms | later / native | threads |');
    console.log('|---|---|---|---|---|---|---|---|');
    for (const r of rows) {
      console.log(
        `| ${r.name} | ${r.tets} | ${r.native.toFixed(0)} | ${r.first.toFixed(0)} | ${(r.first / r.native).toFixed(2)}x | ` +
          `${r.later.toFixed(0)} | ${(r.later / r.native).toFixed(2)}x | ${r.threads} |`,
      );
    }
  });
}

await main();
