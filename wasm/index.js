// Browser and (module) worker entry of the cdt3d package ("default" export
// condition). The .wasm is fetched next to this file; the literal
// new URL('./dist/cdt3d.wasm', import.meta.url) lets bundlers (Vite, webpack)
// see it and emit it as an asset.
import { Cdt3dError, instantiate } from './api.js';
import createCdt3dModule from './dist/cdt3d.js';

export { Cdt3dError };

const wasmUrl = new URL('./dist/cdt3d.wasm', import.meta.url);

/** Loads and instantiates the WebAssembly module; resolves to the cdt3d API. */
export function createCdt3d(options) {
  const defaults = {
    locateFile: (path, prefix) => (path.endsWith('.wasm') ? wasmUrl.href : prefix + path),
  };
  return instantiate(createCdt3dModule, defaults, options);
}
