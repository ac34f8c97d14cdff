// The script of the cdt3d meshing worker (started by worker.js; not meant to
// be imported). In a browser it runs as a module Web Worker and uses the
// browser entry (index.js); under Node it runs in a worker_threads Worker and
// uses the Node entry, whose URL worker.js passes in workerData.
//
// Protocol (requests from worker.js, one answer each, same id):
//   {id, type: 'mesh', bytes: ArrayBuffer, fileName, options, surface?: boolean}
//   {id, type: 'mesh', input: {points, triangles}, options}
//     -> {id, type: 'surface', surface}          (first, when surface is true)
//        {id, type: 'progress', phase, fraction} (any number)
//        {id, type: 'result', result}            (typed-array buffers transferred)
//      | {id, type: 'error', error, surface?}   (error: Cdt3dError.toJSON() + facets)
//   {id, type: 'write', result, format} -> {id, type: 'written', text} | error
//      (text: a string, or a Uint8Array with its buffer transferred for msh, msh-binary, vtu)
//   {id, type: 'readSurface', bytes, fileName} -> {id, type: 'surface', surface} | error
//   {id, type: 'warm', round, options} -> {id, type: 'warmed', ms, threaded} | error
//      (round >= 0 meshes the warm-up model with `options`; -1 only loads the module)
import { Cdt3dError, createCdt3d as createForBrowser } from './index.js';
import { warmUpModel } from './warm-up.js';

// Progress messages are throttled: a phase change, the end, or every 40 ms.
const PROGRESS_INTERVAL_MS = 40;

function serve(createCdt3d, post, listen) {
  let instance = null; // Promise of the cdt3d API, created on first use

  function getCdt() {
    if (instance === null) instance = createCdt3d();
    return instance;
  }

  // Requests are handled one after the other (each is synchronous inside).
  let queue = Promise.resolve();
  listen((msg) => {
    queue = queue.then(() => handle(msg));
  });

  async function handle(msg) {
    const started = performance.now();
    const id = msg?.id;
    let bytes = null;
    let fileName = '';
    try {
      const cdt = await getCdt();
      if (msg.bytes !== undefined) {
        bytes = new Uint8Array(msg.bytes);
        fileName = String(msg.fileName ?? '');
      }
      if (msg.type === 'write') {
        const text = cdt.write(msg.result, msg.format);
        post({ id, type: 'written', text }, typeof text === 'string' ? [] : [text.buffer]);
        return;
      }
      if (msg.type === 'warm') {
        // ms: for round -1 the module's download, compilation and start.
        if (msg.round >= 0) cdt.tetrahedralize(warmUpModel(msg.round), { ...(msg.options ?? {}) });
        post({ id, type: 'warmed', ms: performance.now() - started, threaded: cdt.threaded });
        return;
      }
      if (msg.type === 'readSurface') {
        const surface = plainSurface(cdt.readSurface(bytes, fileName));
        post({ id, type: 'surface', surface }, transferList(surface));
        return;
      }
      if (msg.type !== 'mesh') {
        throw new Cdt3dError('invalid-argument', `cdt3d worker: unknown request type ${JSON.stringify(msg.type)}.`);
      }
      if (msg.surface && bytes !== null && typeof cdt.readSurface === 'function') {
        // The input surface first, so a page can show it while meshing.
        // Errors are left to tetrahedralize, which reports them fully.
        let surface = null;
        try {
          surface = plainSurface(cdt.readSurface(bytes, fileName));
        } catch {}
        if (surface !== null) post({ id, type: 'surface', surface }, transferList(surface));
      }
      const input = bytes !== null ? { bytes, fileName } : msg.input;
      let lastPhase = null;
      let lastTime = 0;
      const options = {
        ...(msg.options ?? {}),
        onProgress: ({ phase, fraction }) => {
          const now = Date.now();
          if (phase !== lastPhase || fraction >= 1 || now - lastTime >= PROGRESS_INTERVAL_MS) {
            lastPhase = phase;
            lastTime = now;
            post({ id, type: 'progress', phase, fraction });
          }
        },
      };
      const result = cdt.tetrahedralize(input, options);
      post({ id, type: 'result', result }, transferList(result));
    } catch (e) {
      const error = errorJSON(e, fileName);
      if (error.code === 'internal') instance = null; // a retired instance: start afresh next time
      const answer = { id, type: 'error', error };
      // For errors that name facets, the input surface lets the page show them.
      if (msg?.type === 'mesh' && bytes !== null && (error.facet >= 0 || error.facets?.length > 0)) {
        try {
          const cdt = await getCdt();
          if (typeof cdt.readSurface === 'function') answer.surface = plainSurface(cdt.readSurface(bytes, fileName));
        } catch {}
      }
      post(answer, answer.surface ? transferList(answer.surface) : []);
    }
  }
}

// readSurface's answer with its error (if any) as a plain object.
function plainSurface(surface) {
  const out = { ...surface };
  if (out.error) out.error = errorJSON(out.error, '');
  else delete out.error;
  return out;
}

// A Cdt3dError as a plain object (Error fields do not survive postMessage).
function errorJSON(e, fileName) {
  if (e instanceof Cdt3dError || (e && typeof e.toJSON === 'function' && typeof e.code === 'string')) {
    const json = e.toJSON();
    if (Array.isArray(e.facets)) json.facets = e.facets.slice();
    else if (ArrayLike(e.facets)) json.facets = Array.from(e.facets);
    return json;
  }
  // A C++ exception that no binding caught reaches here as an opaque object.
  const opaque = typeof WebAssembly.Exception === 'function' && e instanceof WebAssembly.Exception;
  const text = opaque
    ? 'the mesher stopped on an uncaught WebAssembly exception (seen near the heap\'s limit: try a smaller model, or the native cdt3d)'
    : e?.message ?? String(e);
  return new Cdt3dError('internal', `cdt3d worker: ${text}`, { file: fileName }).toJSON();
}

function ArrayLike(v) {
  return ArrayBuffer.isView(v) && !(v instanceof DataView);
}

// The buffers of every typed array among the object's own values. A view that
// does not span its whole buffer (e.g. into WebAssembly memory) is replaced by
// a copy first, so transferring never detaches memory that is not ours.
function transferList(obj) {
  const buffers = new Set();
  for (const key of Object.keys(obj)) {
    let v = obj[key];
    if (!ArrayLike(v)) continue;
    if (v.byteOffset !== 0 || v.byteLength !== v.buffer.byteLength || isShared(v.buffer)) {
      v = obj[key] = v.slice();
    }
    buffers.add(v.buffer);
  }
  return [...buffers];
}

function isShared(buffer) {
  return typeof SharedArrayBuffer !== 'undefined' && buffer instanceof SharedArrayBuffer;
}

// Which world are we in?
const inWebWorker =
  typeof WorkerGlobalScope !== 'undefined' && typeof self !== 'undefined' && self instanceof WorkerGlobalScope;

if (inWebWorker) {
  serve(
    createForBrowser,
    (msg, transfer) => self.postMessage(msg, transfer ?? []),
    (onMessage) => {
      self.onmessage = (e) => onMessage(e.data);
    },
  );
} else if (typeof process === 'object' && typeof process.versions?.node === 'string') {
  // Node: worker_threads. Specifiers in variables keep bundlers from
  // following them into a browser build.
  const threadsModule = 'node:worker_threads';
  import(/* @vite-ignore */ threadsModule).then(async ({ parentPort, workerData }) => {
    if (!parentPort || !workerData?.cdt3dWorker) return; // imported, not started by worker.js
    const { createCdt3d } = await import(/* @vite-ignore */ workerData.entry);
    serve(
      createCdt3d,
      (msg, transfer) => parentPort.postMessage(msg, transfer ?? []),
      (onMessage) => parentPort.on('message', onMessage),
    );
  });
}
