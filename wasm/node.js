// Node entry of the cdt3d package ("node" export condition). The module is
// built for web and worker only (an ES module with a Node environment breaks
// on __dirname), so Node is handed the .wasm bytes directly.
import { readFileSync } from 'node:fs';

import { Cdt3dError, instantiate } from './api.js';
import createCdt3dModule from './dist/cdt3d.js';

export { Cdt3dError };

const wasmUrl = new URL('./dist/cdt3d.wasm', import.meta.url);
let wasmBytes = null;

/** Loads and instantiates the WebAssembly module; resolves to the cdt3d API. */
export async function createCdt3d(options) {
  const defaults = {};
  if (options?.wasmBinary === undefined && options?.locateFile === undefined) {
    if (wasmBytes === null) {
      try {
        wasmBytes = readFileSync(wasmUrl);
      } catch (e) {
        throw new Cdt3dError('io', `Could not read ${wasmUrl.pathname}: ${e.message}`, {
          file: wasmUrl.pathname,
          cause: e,
        });
      }
    }
    defaults.wasmBinary = wasmBytes;
  }
  return instantiate(createCdt3dModule, defaults, options);
}
