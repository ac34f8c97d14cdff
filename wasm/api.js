// The public JS API of cdt3d, built on the raw Embind functions of bindings.cpp.
// Shared by the Node entry (node.js) and the browser/worker entry (index.js),
// which differ only in how the .wasm bytes are found.
//
// The raw functions never throw: they return {ok: true, ...} or
// {ok: false, error: {...}}. This file checks arguments, turns failures into
// Cdt3dError, and retires the instance if the module ever aborts.

const NOT_APPLICABLE = -1;

/** An error reported by cdt3d; the fields match the native CLI's --json error. */
export class Cdt3dError extends Error {
  constructor(code, message, where = {}) {
    super(message, where.cause === undefined ? undefined : { cause: where.cause });
    this.code = code;
    this.file = typeof where.file === 'string' ? where.file : '';
    this.line = location(where.line);
    this.record = location(where.record);
    this.facet = location(where.facet);
    this.vertex = location(where.vertex);
    this.otherFacet = location(where.otherFacet);
  }

  /** Plain object with the same fields as the native CLI's error (survives postMessage). */
  toJSON() {
    return {
      code: this.code,
      message: this.message,
      file: this.file,
      line: this.line,
      record: this.record,
      facet: this.facet,
      vertex: this.vertex,
      otherFacet: this.otherFacet,
    };
  }
}
Object.defineProperty(Cdt3dError.prototype, 'name', {
  value: 'Cdt3dError',
  writable: true,
  configurable: true,
});

function location(v) {
  return Number.isInteger(v) ? v : NOT_APPLICABLE;
}

function invalidArgument(message, file) {
  return new Cdt3dError('invalid-argument', message, { file });
}

// Uint8Array over the caller's bytes, without copying; null if `bytes` is not
// binary data. Accepts Uint8Array (and Node's Buffer), any other typed array or
// DataView, ArrayBuffer and SharedArrayBuffer, also from another realm.
function asBytes(bytes) {
  if (bytes instanceof Uint8Array) return bytes;
  try {
    if (ArrayBuffer.isView(bytes)) {
      return new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    }
    const tag = Object.prototype.toString.call(bytes);
    if (tag === '[object ArrayBuffer]' || tag === '[object SharedArrayBuffer]') {
      return new Uint8Array(bytes);
    }
  } catch {
    // A detached buffer: treated as "not bytes".
  }
  return null;
}

function describe(value) {
  if (value === null || value === undefined) return String(value);
  if (Array.isArray(value)) return 'an Array';
  const kind = typeof value === 'object' ? (value.constructor?.name ?? 'object') : typeof value;
  return `${/^[aeiou]/i.test(kind) ? 'an' : 'a'} ${kind}`;
}

function errorFromRaw(raw) {
  const e = raw.error;
  return new Cdt3dError(e.code, e.message, e);
}

// Wraps one instantiated Embind module. `abortReason()` is the message given to
// the module's onAbort, or null while it is healthy.
function wrap(mod, abortReason) {
  let dead = null;

  // Runs a raw function. A WebAssembly.RuntimeError means the module aborted or
  // trapped: its memory can no longer be trusted, so the instance is retired.
  function call(fn) {
    if (dead !== null) {
      throw new Cdt3dError(
        'internal',
        `This cdt3d instance stopped after an earlier failure (${dead}); create a new one with createCdt3d().`,
      );
    }
    try {
      return fn();
    } catch (e) {
      if (e instanceof WebAssembly.RuntimeError || abortReason() !== null) {
        dead = abortReason() || tidy(e.message ?? '') || 'abort';
        throw new Cdt3dError(
          'internal',
          `The cdt3d WebAssembly module stopped (${dead}): it ran out of memory or hit a bug. ` +
            'Create a new instance with createCdt3d().',
          { cause: e },
        );
      }
      throw e;
    }
  }

  const api = {
    version: mod._version(),
    errorCodes: Object.freeze(mod._errorCodes()),

    readPlc(bytes, fileName) {
      if (typeof fileName !== 'string' || fileName.length === 0) {
        throw invalidArgument(
          `readPlc(bytes, fileName): fileName must be a non-empty string (it picks the format by extension), got ${
            typeof fileName === 'string' ? 'an empty string' : describe(fileName)
          }.`,
          '',
        );
      }
      const data = asBytes(bytes);
      if (data === null) {
        throw invalidArgument(
          `readPlc(bytes, fileName): bytes must be a Uint8Array, an ArrayBuffer or a Buffer, got ${describe(bytes)}.`,
          fileName,
        );
      }
      const raw = call(() => mod._readPlc(data, fileName));
      if (!raw.ok) throw errorFromRaw(raw);
      return {
        file: raw.file,
        fileVertices: raw.fileVertices,
        points: raw.points,
        welded: raw.welded,
        unreferenced: raw.unreferenced,
        facets: raw.facets,
        triangles: raw.triangles,
        loops: raw.loops,
        segments: raw.segments,
        holes: raw.holes,
        regions: raw.regions,
        bboxMin: raw.bboxMin,
        bboxMax: raw.bboxMax,
      };
    },

    memoryUsage() {
      return call(() => mod._memoryUsage());
    },
  };
  return Object.freeze(api);
}

/**
 * Instantiates the Emscripten factory and wraps it. `defaults` are the entry's
 * module arguments (how to find the .wasm); `options` the caller's, checked.
 */
export async function instantiate(factory, defaults, options) {
  if (options === undefined || options === null) options = {};
  if (typeof options !== 'object') {
    throw invalidArgument(`createCdt3d(options): options must be an object, got ${describe(options)}.`, '');
  }
  const args = { ...defaults };
  if (options.wasmBinary !== undefined) {
    const binary = asBytes(options.wasmBinary);
    if (binary === null) {
      throw invalidArgument(
        `createCdt3d(options): wasmBinary must be an ArrayBuffer or a Uint8Array, got ${describe(options.wasmBinary)}.`,
        '',
      );
    }
    args.wasmBinary = binary;
  }
  if (options.locateFile !== undefined) {
    if (typeof options.locateFile !== 'function') {
      throw invalidArgument(
        `createCdt3d(options): locateFile must be a function, got ${describe(options.locateFile)}.`,
        '',
      );
    }
    args.locateFile = options.locateFile;
  }
  let reason = null;
  args.onAbort = (what) => {
    reason = what === undefined || what === null ? '' : tidy(String(what));
  };
  // The runtime's own stderr lines (the core prints nothing) repeat what the
  // abort reason says; keep them out of the console.
  args.printErr = () => {};
  let mod;
  try {
    mod = await factory(args);
  } catch (e) {
    throw new Cdt3dError(
      'internal',
      `Could not start the cdt3d WebAssembly module: ${tidy(e?.message ?? String(e))}`,
      { cause: e },
    );
  }
  return wrap(mod, () => reason);
}

// Drops the runtime's advice to rebuild with assertions, useless to users.
function tidy(message) {
  return message.replace(/\.?\s*Build with -s ASSERTIONS=1 for more info\.?/g, '');
}
