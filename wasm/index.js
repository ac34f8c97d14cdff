// Browser and (module) worker entry of the cdt3d package ("default" export
// condition). The .wasm is fetched next to this file and compiled while it
// downloads (WebAssembly.instantiateStreaming); the literal
// new URL('./dist/...', import.meta.url) lets bundlers (Vite, webpack) see
// the files and emit them as assets.
//
// Two modules: the single-threaded one (dist/), which works everywhere, and
// the two-thread one (dist/threads/, Emscripten pthreads), which needs
// SharedArrayBuffer and so a cross-origin isolated page (COOP/COEP headers).
import { Cdt3dError, instantiate } from './api.js';
import createCdt3dModule from './dist/cdt3d.js';

export { Cdt3dError };

const wasmUrl = new URL('./dist/cdt3d.wasm', import.meta.url);
// The two-thread module is imported by URL at run time, not bundled: its
// pool worker (cdt3d.worker.js) imports the same script file by that URL.
const threadsJsUrl = new URL('./dist/threads/cdt3d.js', import.meta.url);
const threadsWasmUrl = new URL('./dist/threads/cdt3d.wasm', import.meta.url);
const threadsWorkerUrl = new URL('./dist/threads/cdt3d.worker.js', import.meta.url);

// Past this the two-thread module is given up for the single-threaded one:
// a pool worker that fails to load leaves Emscripten's start-up waiting
// forever.
const THREADS_START_MS = 10_000;

function canShareMemory() {
  return globalThis.crossOriginIsolated === true && typeof SharedArrayBuffer === 'function';
}

async function createThreaded(args) {
  // A pool worker script that is missing (say, a bundler did not emit it)
  // fails before Emscripten listens for its errors: ask first.
  if (threadsWorkerUrl.protocol === 'http:' || threadsWorkerUrl.protocol === 'https:') {
    const head = await fetch(threadsWorkerUrl, { method: 'HEAD' }).catch(() => null);
    if (!head?.ok) throw new Error(`its worker script ${threadsWorkerUrl.href} is missing`);
  }
  const { default: create } = await import(/* @vite-ignore */ threadsJsUrl.href);
  let timer;
  let onError;
  const failed = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Error('its thread pool did not start')), THREADS_START_MS);
    // A pool worker that cannot load makes Emscripten rethrow its error
    // event here, uncaught; taken as the start's failure, it is kept from
    // ending the caller's worker.
    onError = (e) => {
      e.preventDefault();
      reject(new Error(`its thread pool failed: ${e.message || 'the worker did not load'}`));
    };
    globalThis.addEventListener?.('error', onError);
  });
  try {
    return await Promise.race([create(args), failed]);
  } finally {
    clearTimeout(timer);
    globalThis.removeEventListener?.('error', onError);
  }
}

/**
 * Loads and instantiates the WebAssembly module; resolves to the cdt3d API.
 * The two-thread module when the page is cross-origin isolated (unless
 * `threads: false`), the single-threaded one otherwise or if that fails.
 */
export async function createCdt3d(options) {
  if (options?.threads !== undefined && typeof options.threads !== 'boolean') {
    throw new Cdt3dError(
      'invalid-argument',
      `createCdt3d(options): threads must be a boolean, got ${typeof options.threads}.`,
    );
  }
  // A caller's wasmBinary or locateFile names the single-threaded module.
  const own = options?.wasmBinary === undefined && options?.locateFile === undefined;
  if (own && options?.threads !== false && canShareMemory()) {
    const defaults = {
      locateFile: (path) => (path.endsWith('.wasm') ? threadsWasmUrl.href : threadsWorkerUrl.href),
      mainScriptUrlOrBlob: threadsJsUrl.href,
    };
    try {
      return await instantiate(createThreaded, defaults, options);
    } catch {
      // no second thread to be had here: the single-threaded module below
    }
  }
  const defaults = {
    locateFile: (path, prefix) => (path.endsWith('.wasm') ? wasmUrl.href : prefix + path),
  };
  return instantiate(createCdt3dModule, defaults, options);
}
