// Node entry of the cdt3d package ("node" export condition).
//
// Node always has shared memory and worker_threads, so by default it gets
// the two-thread module (dist/node/, built with Emscripten's pthreads): the
// pipeline's work beside steps 1-2 runs on a second core, as in the native CLI.
// That module is CommonJS, because Emscripten 3.1.6's ES module output breaks
// under Node (on __dirname). The single-threaded ES module (dist/cdt3d.js,
// built for web and worker) is the fallback: with `threads: false`, with a
// caller's wasmBinary or locateFile (which name that module's .wasm), or when
// the two-thread module is missing or cannot start. Node is handed the .wasm
// bytes directly either way.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';

import { Cdt3dError, instantiate } from './api.js';
import createCdt3dModule from './dist/cdt3d.js';

export { Cdt3dError };

const wasmUrl = new URL('./dist/cdt3d.wasm', import.meta.url);
const threadedUrl = new URL('./dist/node/cdt3d.wasm', import.meta.url);
let wasmBytes = null;
let threadedBytes = null;

function readWasm(url) {
  try {
    return readFileSync(url);
  } catch (e) {
    throw new Cdt3dError('io', `Could not read ${url.pathname}: ${e.message}`, {
      file: url.pathname,
      cause: e,
    });
  }
}

// The two-thread module's factory, or null when it is not built.
function threadedFactory() {
  let create;
  try {
    create = createRequire(import.meta.url)('./dist/node/cdt3d.js');
    if (threadedBytes === null) threadedBytes = readFileSync(threadedUrl);
  } catch {
    return null;
  }
  return async (args) => {
    const mod = await create({ ...args, wasmBinary: threadedBytes });
    // The pool's worker thread must not keep the process alive once the
    // caller is done; it is only busy inside a (synchronous) call.
    for (const w of mod.PThread?.unusedWorkers ?? []) w.unref?.();
    return mod;
  };
}

/** Loads and instantiates the WebAssembly module; resolves to the cdt3d API. */
export async function createCdt3d(options) {
  const own = options?.wasmBinary === undefined && options?.locateFile === undefined;
  if (options?.threads !== undefined && typeof options.threads !== 'boolean') {
    throw new Cdt3dError(
      'invalid-argument',
      `createCdt3d(options): threads must be a boolean, got ${typeof options.threads}.`,
    );
  }
  if (own && options?.threads !== false) {
    const factory = threadedFactory();
    if (factory !== null) {
      try {
        return await instantiate(factory, {}, options);
      } catch {
        // no second thread to be had here: the single-threaded module below
      }
    }
  }
  const defaults = {};
  if (own) {
    if (wasmBytes === null) wasmBytes = readWasm(wasmUrl);
    defaults.wasmBinary = wasmBytes;
  }
  return instantiate(createCdt3dModule, defaults, options);
}
