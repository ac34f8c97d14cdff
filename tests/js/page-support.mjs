// What the real-browser page suites share with the page bench
// (tests/js/web.test.mjs, tests/bench/bench_page.mjs): a production build of
// web/, a static server for it, headless Chromium, and the main thread's
// long tasks and long animation frames recorded from the page's start.
import { existsSync, mkdtempSync, readFileSync, rmSync, statSync } from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const repoRoot = fileURLToPath(new URL('../../', import.meta.url));

export const chromiumPath = process.env.CHROMIUM_PATH || '/usr/bin/chromium';

const MIME = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.wasm': 'application/wasm',
  '.json': 'application/json',
  '.svg': 'image/svg+xml',
};

/** Builds the page as `npx vite build web` does, into `outDir`. */
export async function buildPage(outDir) {
  const { build } = await import('vite');
  await build({
    configFile: path.join(repoRoot, 'web', 'vite.config.js'),
    logLevel: 'warn',
    build: { outDir, emptyOutDir: true },
  });
}

/**
 * Serves `dir` on 127.0.0.1 (random port), uncached. With `isolated` true
 * (changeable later) it sends the COOP/COEP headers of web/README.md, which
 * make the page cross-origin isolated. Resolves to {server, origin, isolated}.
 */
export async function servePage(dir, { isolated = true } = {}) {
  const handle = { server: null, origin: '', isolated };
  handle.server = http.createServer((req, res) => {
    let rel = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    if (rel.endsWith('/')) rel += 'index.html';
    const file = path.join(dir, rel);
    if (!file.startsWith(dir + path.sep) || !existsSync(file) || !statSync(file).isFile()) {
      res.writeHead(404, { 'content-type': 'text/plain' });
      res.end('not found');
      return;
    }
    const headers = { 'content-type': MIME[path.extname(file)] ?? 'application/octet-stream', 'cache-control': 'no-store' };
    if (handle.isolated) {
      headers['cross-origin-opener-policy'] = 'same-origin';
      headers['cross-origin-embedder-policy'] = 'require-corp';
    }
    res.writeHead(200, headers);
    res.end(readFileSync(file));
  });
  await new Promise((resolve) => handle.server.listen(0, '127.0.0.1', resolve));
  handle.origin = `http://127.0.0.1:${handle.server.address().port}`;
  return handle;
}

/** Headless Chromium with a fresh profile folder `profile`: a playwright-core context. */
export async function launchChromium(profile) {
  const { chromium } = await import('playwright-core');
  return chromium.launchPersistentContext(profile, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 1280, height: 800 },
    // WebGL through SwiftShader (no GPU here). Not --disable-gpu: that makes
    // the compositor read every WebGL frame back on the main thread
    // (GLES2::ReadPixels in Commit), which shows up as long tasks that a
    // page on a real GPU never has.
    args: [
      '--headless', '--no-sandbox', '--use-angle=swiftshader', '--use-gl=angle',
      '--enable-unsafe-swiftshader', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
    ],
  });
}

/**
 * An init script (page.addInitScript / context.addInitScript): records the
 * main thread's long tasks in window.__longTasks and its long animation
 * frames in window.__longFrames, with the time the page's own scripts ran in
 * each (`scripts`: the attribution Chromium gives per script over 5 ms;
 * `layout`: style and layout the scripts forced). A frame's duration also
 * counts the browser's rendering, which with a software GPU can be long
 * without any work of the page.
 */
export function recordLongTasks() {
  window.__longTasks = [];
  window.__longFrames = [];
  try {
    new PerformanceObserver((list) => {
      for (const e of list.getEntries()) window.__longTasks.push({ start: e.startTime, duration: e.duration });
    }).observe({ type: 'longtask', buffered: true });
  } catch {}
  try {
    new PerformanceObserver((list) => {
      for (const e of list.getEntries()) {
        window.__longFrames.push({
          start: e.startTime,
          duration: e.duration,
          layout: e.forcedStyleAndLayoutDuration ?? 0,
          scripts: (e.scripts ?? []).map((s) => ({
            duration: s.duration,
            invoker: s.invoker,
            source: `${s.sourceURL ?? ''}:${s.sourceFunctionName ?? ''}`,
          })),
        });
      }
    }).observe({ type: 'long-animation-frame', buffered: true });
  } catch {}
}

/**
 * For the page benches: builds the page into a temporary folder, serves it
 * (`isolated` as in servePage), launches Chromium on a temporary profile and
 * runs `fn(context, origin)`; everything is closed and removed afterwards.
 */
export async function withServedPage({ isolated = true } = {}, fn) {
  const buildDir = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-bench-web-'));
  const profile = mkdtempSync(path.join(os.tmpdir(), 'cdt3d-bench-chromium-'));
  let served;
  let context;
  try {
    await buildPage(buildDir);
    served = await servePage(buildDir, { isolated });
    context = await launchChromium(profile);
    return await fn(context, served.origin);
  } finally {
    await context?.close().catch(() => {});
    served?.server.close();
    rmSync(profile, { recursive: true, force: true });
    rmSync(buildDir, { recursive: true, force: true });
  }
}
