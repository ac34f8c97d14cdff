// The page rows of the scale bench (bench_scale.sh): each MODEL opened
// through the demo page's file input in headless Chromium, on a fresh page
// (a fresh worker and WebAssembly heap), with the page's default options
// (validation included). Prints one JSON line per model: the final state,
// the tets, the core's clock (msTotal), the seconds from opening the file
// to the end of meshing and to the mesh being shown, and for an error its
// code and message. A bench, not a test: it asserts nothing.
//
//   node tests/bench/page_scale.mjs MODEL...
//
// Needs the WASM build (tests/scripts/build.sh) and /usr/bin/chromium (or
// $CHROMIUM_PATH). PAGE_TIMEOUT (seconds, default 900) per model;
// PAGE_VALIDATE=0 unticks the page's "validate" box first (validation
// needs more heap than meshing, so the page takes larger models without it).
import { existsSync } from 'node:fs';
import path from 'node:path';

import { chromiumPath, withServedPage } from '../js/page-support.mjs';

const timeoutMs = 1000 * (Number(process.env.PAGE_TIMEOUT) || 900);

async function meshOnPage(context, origin, file) {
  for (const p of context.pages()) await p.close();
  const page = await context.newPage();
  await page.goto(`${origin}/?model=`);
  await page.waitForFunction(() => ['ready', 'failed'].includes(document.body.dataset.engine), null, {
    timeout: 300_000,
  });
  if (process.env.PAGE_VALIDATE === '0') await page.uncheck('#opt-validate');
  const t0 = Date.now();
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => window.cdt3dDemo.timings.length > 0, null, { timeout: 60_000 });
  await page.waitForFunction(() => ['done', 'error', 'cancelled'].includes(document.body.dataset.state), null, {
    timeout: timeoutMs,
    polling: 500,
  });
  const seen = await page.evaluate(() => {
    const demo = window.cdt3dDemo;
    const t = demo.timings.at(-1);
    return {
      state: document.body.dataset.state,
      tets: demo.stats?.tets ?? 0,
      msTotal: demo.stats?.msTotal ?? null,
      meshS: (t.meshEnd - t.start) / 1000,
      shownS: Number.isFinite(t.shown) ? (t.shown - t.start) / 1000 : null,
      code: demo.error?.code ?? null,
      message: demo.error?.message ?? null,
      threaded: demo.engine.threaded,
      validate: document.getElementById('opt-validate').checked,
      // An error panel's way on: "Mesh without validation" for a model over
      // the heap's limit with validation.
      offersNoValidate: !document.getElementById('no-validate').hidden,
    };
  });
  return { model: path.basename(file), wallS: (Date.now() - t0) / 1000, ...seen };
}

async function main() {
  const files = process.argv.slice(2).map((f) => path.resolve(f));
  if (files.length === 0) {
    console.error('usage: node tests/bench/page_scale.mjs MODEL...');
    process.exit(2);
  }
  if (!existsSync(chromiumPath)) {
    console.error(`page_scale: Chromium not found at ${chromiumPath} (set CHROMIUM_PATH).`);
    process.exit(2);
  }
  await withServedPage({ isolated: true }, async (context, origin) => {
    for (const file of files) {
      let row;
      try {
        row = await meshOnPage(context, origin, file);
      } catch (e) {
        row = { model: path.basename(file), state: 'failed', message: String(e?.message ?? e).split('\n')[0] };
      }
      console.log(JSON.stringify(row));
    }
  });
}

await main();
