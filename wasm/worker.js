// Meshing off the main thread: `cdt3d/worker`. The WebAssembly module runs in
// a module Web Worker (browsers) or a worker_threads Worker (Node 20), started
// from worker-entry.js. Input bytes and result arrays are transferred, not
// copied. Cancelling terminates the worker (a synchronous WebAssembly call
// cannot be interrupted otherwise); a reusable worker starts a fresh one for
// the next job.
import { Cdt3dError } from './api.js';

const isNode =
  typeof process === 'object' &&
  typeof process.versions?.node === 'string' &&
  typeof window === 'undefined' &&
  typeof WorkerGlobalScope === 'undefined';

// Kept out of `new URL(literal, import.meta.url)` so bundlers do not treat the
// Node-only files as browser assets.
const here = import.meta.url;

function cancelledError(signal, fileName) {
  const reason = signal?.reason;
  const why = reason instanceof Error && reason.name !== 'AbortError' ? `: ${reason.message}` : '';
  return new Cdt3dError('cancelled', `Meshing was cancelled${why}.`, { file: fileName ?? '' });
}

function fromJSON(json, extra = {}) {
  const e = new Cdt3dError(json?.code ?? 'internal', json?.message ?? 'cdt3d worker failed', json ?? {});
  if (Array.isArray(json?.facets)) e.facets = json.facets;
  if (extra.surface) e.surface = extra.surface;
  return e;
}

// The portable bits of a worker: start, post, listen, stop.
async function spawn(onMessage, onFailure) {
  if (isNode) {
    const threadsModule = 'node:worker_threads';
    const { Worker } = await import(/* @vite-ignore */ threadsModule);
    const w = new Worker(new URL('./worker-entry.js', here), {
      // A parent started with `node --input-type=module -e ...` would pass
      // --input-type on, which a file-based worker refuses.
      execArgv: process.execArgv.filter((a) => !a.startsWith('--input-type')),
      workerData: { cdt3dWorker: true, entry: new URL('./node.js', here).href },
    });
    w.on('message', onMessage);
    w.on('error', (e) => onFailure(`the cdt3d worker failed: ${e?.message ?? e}`));
    w.on('exit', (code) => onFailure(`the cdt3d worker exited (code ${code})`));
    return {
      post: (msg, transfer) => w.postMessage(msg, transfer),
      stop: () => {
        w.removeAllListeners('exit');
        w.removeAllListeners('error');
        w.on('error', () => {});
        return w.terminate();
      },
      ref: () => w.ref(),
      unref: () => w.unref(),
    };
  }
  const w = new Worker(new URL('./worker-entry.js', import.meta.url), { type: 'module', name: 'cdt3d' });
  w.onmessage = (e) => onMessage(e.data);
  w.onerror = (e) => {
    e.preventDefault?.();
    onFailure(`the cdt3d worker failed${e?.message ? `: ${e.message}` : ' to load'}`);
  };
  w.onmessageerror = () => onFailure('the cdt3d worker sent a message that could not be read');
  return { post: (msg, transfer) => w.postMessage(msg, transfer), stop: () => w.terminate(), ref() {}, unref() {} };
}

// Bytes to send: a whole ArrayBuffer is transferred; a view that spans its
// whole (non-shared) buffer transfers that buffer; anything else is copied.
async function toBuffer(file, transfer) {
  if (typeof Blob !== 'undefined' && file instanceof Blob) return file.arrayBuffer();
  const tag = Object.prototype.toString.call(file);
  if (tag === '[object ArrayBuffer]') return transfer ? file : file.slice(0);
  if (ArrayBuffer.isView(file)) {
    const whole =
      file.byteOffset === 0 &&
      file.byteLength === file.buffer.byteLength &&
      Object.prototype.toString.call(file.buffer) === '[object ArrayBuffer]';
    if (whole && transfer) return file.buffer;
    return new Uint8Array(file.buffer, file.byteOffset, file.byteLength).slice().buffer;
  }
  return null;
}

function isArrays(input) {
  return input && typeof input === 'object' && ArrayBuffer.isView(input.points) && ArrayBuffer.isView(input.triangles);
}

function describe(v) {
  if (v === null || v === undefined) return String(v);
  return typeof v === 'object' ? `a ${v.constructor?.name ?? 'object'}` : `a ${typeof v}`;
}

/**
 * A worker that stays alive between jobs (the WebAssembly module is
 * instantiated once). Jobs run one at a time, in order.
 * @param {{workerUrl?: never}} [settings] reserved
 */
export function createMeshWorker() {
  let worker = null; // {post, stop, ref, unref} once started
  let starting = null; // Promise of the worker while it starts
  let nextId = 1;
  let current = null; // the job running in the worker
  const waiting = []; // jobs not yet posted
  let closed = false;

  function failAll(message) {
    const jobs = current ? [current, ...waiting.splice(0)] : waiting.splice(0);
    current = null;
    dropWorker();
    for (const job of jobs) job.reject(new Cdt3dError('internal', `${message}.`, { file: job.fileName ?? '' }));
  }

  function dropWorker() {
    const w = worker;
    worker = null;
    starting = null;
    if (w) w.stop();
  }

  function getWorker() {
    if (worker) return Promise.resolve(worker);
    if (!starting) {
      starting = spawn(onMessage, (why) => failAll(why)).then((w) => {
        if (starting === null) {
          w.stop(); // dropped while starting
          return getWorker();
        }
        worker = w;
        return w;
      });
    }
    return starting;
  }

  function onMessage(msg) {
    const job = current;
    if (!job || msg?.id !== job.id) return; // from a cancelled job
    if (msg.type === 'progress') {
      if (job.onProgress) callSafely(job.onProgress, { phase: msg.phase, fraction: msg.fraction });
      return;
    }
    if (msg.type === 'surface' && job.type === 'mesh') {
      if (job.onSurface) callSafely(job.onSurface, msg.surface);
      return;
    }
    finish(job);
    if (msg.type === 'error') job.reject(fromJSON(msg.error, { surface: msg.surface }));
    else if (msg.type === 'result') job.resolve(msg.result);
    else if (msg.type === 'written') job.resolve(msg.text);
    else if (msg.type === 'surface') job.resolve(msg.surface);
    else if (msg.type === 'warmed') job.resolve(msg);
    else job.reject(new Cdt3dError('internal', `cdt3d worker: unexpected answer ${JSON.stringify(msg.type)}.`));
    pump();
  }

  function finish(job) {
    current = null;
    job.cleanup();
    if (waiting.length === 0 && worker) worker.unref();
  }

  async function pump() {
    if (current || waiting.length === 0) return;
    const job = waiting.shift();
    current = job;
    let w;
    try {
      w = await getWorker();
    } catch (e) {
      if (current === job) {
        finish(job);
        job.reject(new Cdt3dError('internal', `Could not start the cdt3d worker: ${e?.message ?? e}`, { cause: e }));
        pump();
      }
      return;
    }
    if (current !== job) return; // cancelled while the worker started
    w.ref();
    try {
      w.post(job.message, job.transfer);
    } catch (e) {
      finish(job);
      job.reject(new Cdt3dError('invalid-argument', `Could not send the job to the cdt3d worker: ${e?.message ?? e}`));
      pump();
    }
  }

  function submit(type, fileName, buildMessage, { signal, onProgress, onSurface } = {}) {
    if (closed) return Promise.reject(new Cdt3dError('invalid-argument', 'This mesh worker was terminated.'));
    if (signal?.aborted) return Promise.reject(cancelledError(signal, fileName));
    return new Promise((resolve, reject) => {
      const job = { id: nextId++, type, fileName, onProgress, onSurface, resolve, reject, cleanup: () => {} };
      const onAbort = () => {
        if (current === job) {
          // The job is inside a synchronous WebAssembly call: stop the worker.
          current = null;
          dropWorker();
          pump();
        } else {
          const i = waiting.indexOf(job);
          if (i >= 0) waiting.splice(i, 1);
        }
        job.cleanup();
        reject(cancelledError(signal, fileName));
      };
      if (signal) {
        signal.addEventListener('abort', onAbort, { once: true });
        job.cleanup = () => signal.removeEventListener('abort', onAbort);
      }
      // Reading a Blob is asynchronous; the job joins the queue afterwards,
      // unless it was cancelled meanwhile.
      Promise.resolve(buildMessage(job.id)).then(
        (built) => {
          if (signal?.aborted) return;
          job.message = built.message;
          job.transfer = built.transfer;
          waiting.push(job);
          pump();
        },
        (e) => {
          job.cleanup();
          reject(e);
        },
      );
    });
  }

  async function bytesMessage(id, type, file, fileName, transfer, extra) {
    const buffer = await toBuffer(file, transfer);
    if (buffer === null) {
      throw new Cdt3dError(
        'invalid-argument',
        `${type}: the input must be a File, Blob, ArrayBuffer or Uint8Array (or {points, triangles}), got ${describe(file)}.`,
        { file: fileName ?? '' },
      );
    }
    if (typeof fileName !== 'string' || fileName === '') {
      throw new Cdt3dError(
        'invalid-argument',
        `${type}: a fileName (it picks the format by extension) is needed for an ${describe(file).slice(2)} input.`,
      );
    }
    const shared = Object.prototype.toString.call(buffer) === '[object SharedArrayBuffer]';
    return { message: { id, type, bytes: buffer, fileName, ...extra }, transfer: shared ? [] : [buffer] };
  }

  return {
    /**
     * Meshes `file` in the worker: like cdt.tetrahedralize(input, options).
     * File/Blob names give the format; for bytes pass `fileName`.
     * ArrayBuffers (and Uint8Arrays spanning their buffer) are transferred:
     * they are detached afterwards. Pass `transfer: false` to copy instead.
     */
    mesh(file, options = {}, extra = {}) {
      const { onProgress: optProgress, signal: optSignal, ...rest } = options ?? {};
      const onProgress = extra.onProgress ?? optProgress;
      const signal = extra.signal ?? optSignal;
      const fileName = extra.fileName ?? (typeof Blob !== 'undefined' && file instanceof Blob ? file.name : undefined);
      const transfer = extra.transfer !== false;
      return submit(
        'mesh',
        fileName,
        async (id) => {
          if (isArrays(file)) {
            const points = transfer ? file.points : file.points.slice();
            const triangles = transfer ? file.triangles : file.triangles.slice();
            const buffers = new Set([points.buffer, triangles.buffer]);
            return {
              message: { id, type: 'mesh', input: { points, triangles }, options: rest },
              transfer: [...buffers].filter((b) => Object.prototype.toString.call(b) === '[object ArrayBuffer]'),
            };
          }
          return bytesMessage(id, 'mesh', file, fileName, transfer, { options: rest, surface: !!extra.onSurface });
        },
        { signal, onProgress, onSurface: extra.onSurface },
      );
    },

    /** The input surface of a model: {points, triangles, triangleFacets} (cdt.readSurface). */
    readSurface(file, { fileName, signal } = {}) {
      const name = fileName ?? (typeof Blob !== 'undefined' && file instanceof Blob ? file.name : undefined);
      return submit('readSurface', name, (id) => bytesMessage(id, 'readSurface', file, name, false, {}), { signal });
    },

    /**
     * cdt.write(result, format) in the worker: a string for 'node', 'ele', 'face', 'vtk', 'mesh',
     * a Uint8Array for 'msh', 'msh-binary', 'vtu'; the result is copied.
     */
    write(result, format, { signal } = {}) {
      return submit('write', '', (id) => ({ message: { id, type: 'write', result, format }, transfer: [] }), { signal });
    },

    /**
     * Starts the worker and instantiates the WebAssembly module now (it is
     * compiled while it downloads), then meshes built-in models (warm-up.js:
     * three small ones, then a large one) `rounds` times with `options` (the
     * options the caller's models will use), so that the engine has optimised the hot functions before the
     * first real model: a cold module runs its first large model several
     * times slower. Warm-up gives way to real jobs: it stops as soon as one
     * is submitted. Resolves to {threaded, loadMs, runs: [ms of each round]}.
     */
    async prepare({ rounds = 4, options = {}, signal } = {}) {
      if (!Number.isInteger(rounds) || rounds < 0) {
        throw new Cdt3dError('invalid-argument', `prepare: rounds must be a non-negative integer, got ${rounds}.`);
      }
      // Plain data only: callbacks and signals cannot be posted.
      const plain = Object.fromEntries(
        Object.entries(options ?? {}).filter(([k, v]) => typeof v !== 'function' && k !== 'signal'),
      );
      const warm = (round) =>
        submit('warm', '', (id) => ({ message: { id, type: 'warm', round, options: plain }, transfer: [] }), { signal });
      const loaded = await warm(-1);
      const runs = [];
      for (let round = 0; round < rounds; round++) {
        if (current !== null || waiting.length > 0 || closed) break; // a real job goes first
        runs.push((await warm(round)).ms);
      }
      return { threaded: loaded.threaded, loadMs: loaded.ms, runs };
    },

    /** True while a job is running or waiting. */
    get busy() {
      return current !== null || waiting.length > 0;
    },

    /** Stops the worker; running and waiting jobs are rejected with "cancelled". */
    terminate() {
      closed = true;
      const jobs = current ? [current, ...waiting.splice(0)] : waiting.splice(0);
      current = null;
      dropWorker();
      for (const job of jobs) {
        job.cleanup();
        job.reject(new Cdt3dError('cancelled', 'The mesh worker was terminated.', { file: job.fileName ?? '' }));
      }
    },
  };
}

function callSafely(fn, arg) {
  try {
    fn(arg);
  } catch (e) {
    setTimeout(() => {
      throw e;
    });
  }
}

/**
 * Meshes one model in a worker of its own, which is stopped afterwards.
 * @param file File | Blob | ArrayBuffer | Uint8Array | {points, triangles}
 * @param options tetrahedralize options (keepConvexHull, validate, quality, ...; plain data, posted to the worker)
 * @param extra {onProgress, signal, fileName, onSurface, transfer}
 * @returns Promise of the tetrahedralize result; rejects with Cdt3dError
 *   ("cancelled" when `signal` aborts).
 */
export function meshInWorker(file, options = {}, extra = {}) {
  const w = createMeshWorker();
  const done = w.mesh(file, options, extra);
  return done.finally(() => w.terminate());
}
