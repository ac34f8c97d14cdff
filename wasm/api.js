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
    this.segment = location(where.segment);
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
      segment: this.segment,
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


const WRITE_FORMATS = ['node', 'ele', 'face', 'vtk', 'mesh', 'msh', 'msh-binary', 'vtu'];
const DEGENERACY_MODES = ['symbolic', 'paper'];
const PHASES = ['read', 'delaunay', 'segments', 'degeneracy', 'facets', 'carve', 'refine', 'done'];
const OPTION_TYPES = {
  keepConvexHull: 'boolean',
  validate: 'boolean',
  checkIntersections: 'boolean',
  keepTriangles: 'boolean',
  mergeCoplanarFacets: 'boolean',
  repair: 'boolean or object',
  degeneracy: 'string',
  verbosity: 'number',
  stopAfter: 'string',
  quality: 'boolean or object',
  onProgress: 'function',
  signal: 'object',
};
// The fields of options.quality and their defaults (the core's QualityOptions;
// maxVolume -1: no bound, maxPoints 0: the core's own limit).
const QUALITY_DEFAULTS = { radiusEdge: 2, maxVolume: -1, minDihedral: 15, maxPoints: 0 };
// The file a readPlc() summary came from, so that it can be meshed directly.
const SOURCE = Symbol('cdt3d.source');

function withSource(data, fileName, info) {
  Object.defineProperty(info, SOURCE, { value: { data: data.slice(), fileName } });
  return info;
}

function cancelled(file) {
  return new Cdt3dError('cancelled', 'Meshing was cancelled.', { file });
}

function checkOptions(options) {
  if (options === undefined || options === null) options = {};
  if (typeof options !== 'object' || Array.isArray(options)) {
    throw invalidArgument(`tetrahedralize(input, options): options must be an object, got ${describe(options)}.`, '');
  }
  for (const [key, value] of Object.entries(options)) {
    const type = OPTION_TYPES[key];
    if (type === undefined) {
      throw invalidArgument(
        `tetrahedralize: unknown option "${key}" (known: ${Object.keys(OPTION_TYPES).join(', ')}).`,
        '',
      );
    }
    if (key === 'quality' || key === 'repair') continue; // checkQuality(), checkRepair()
    if (value !== undefined && typeof value !== type) {
      throw invalidArgument(`tetrahedralize: option "${key}" must be a ${type}, got ${describe(value)}.`, '');
    }
  }
  const verbosity = options.verbosity ?? 0;
  if (!Number.isInteger(verbosity) || verbosity < 0 || verbosity > 2) {
    throw invalidArgument(`tetrahedralize: option "verbosity" must be 0, 1 or 2, got ${verbosity}.`, '');
  }
  const stopAfter = options.stopAfter ?? 'done';
  if (!PHASES.includes(stopAfter) || stopAfter === 'read') {
    throw invalidArgument(
      `tetrahedralize: option "stopAfter" must be one of ${PHASES.slice(1).join(', ')}, got "${stopAfter}".`,
      '',
    );
  }
  const degeneracy = options.degeneracy ?? 'symbolic';
  if (!DEGENERACY_MODES.includes(degeneracy)) {
    throw invalidArgument(
      `tetrahedralize: option "degeneracy" must be one of ${DEGENERACY_MODES.join(', ')}, got "${degeneracy}".`,
      '',
    );
  }
  const signal = options.signal ?? null;
  if (signal !== null && typeof signal.aborted !== 'boolean') {
    throw invalidArgument('tetrahedralize: option "signal" must be an AbortSignal.', '');
  }
  const quality = checkQuality(options.quality);
  const repair = checkRepair(options.repair, 'tetrahedralize: option "repair"');
  return {
    keepConvexHull: options.keepConvexHull ?? false,
    validate: options.validate ?? false,
    checkIntersections: options.checkIntersections ?? true,
    // mergeCoplanarFacets: the old name of the default (flat faces merged).
    keepTriangles: options.keepTriangles ?? (options.mergeCoplanarFacets === false),
    repair: repair !== null,
    fillHoles: repair?.fillHoles ?? false,
    unionOfParts: repair?.union ?? true,
    partsAsRegions: repair?.partsAsRegions ?? false,
    degeneracy,
    verbosity,
    stopAfter,
    quality,
    onProgress: options.onProgress ?? null,
    signal,
  };
}

// options.repair: true or {fillHoles?: boolean, union?: boolean,
// partsAsRegions?: boolean} repairs first (union defaults to true); false,
// null or undefined do not. Returns null (no repair) or {fillHoles, union,
// partsAsRegions}.
const REPAIR_FIELDS = ['fillHoles', 'union', 'partsAsRegions'];
function checkRepair(repair, what) {
  if (repair === undefined || repair === null || repair === false) return null;
  if (repair === true) return { fillHoles: false, union: true, partsAsRegions: false };
  if (typeof repair !== 'object' || Array.isArray(repair)) {
    throw invalidArgument(`${what} must be true or an object {fillHoles?: boolean, union?: boolean, partsAsRegions?: boolean}, got ${describe(repair)}.`, '');
  }
  for (const [key, value] of Object.entries(repair)) {
    if (!REPAIR_FIELDS.includes(key)) {
      throw invalidArgument(`${what}: unknown field "${key}" (known: ${REPAIR_FIELDS.join(', ')}).`, '');
    }
    if (value !== undefined && typeof value !== 'boolean') {
      throw invalidArgument(`${what}: ${key} must be a boolean, got ${describe(value)}.`, '');
    }
  }
  const checked = {
    fillHoles: repair.fillHoles ?? false,
    union: repair.union ?? true,
    partsAsRegions: repair.partsAsRegions ?? false,
  };
  if (checked.partsAsRegions && !checked.union) {
    throw invalidArgument(`${what}: partsAsRegions keeps the union of the parts; it cannot go with union: false.`, '');
  }
  return checked;
}

// options.quality: true or an object turns quality refinement on (every
// field it leaves out at its default); false, null or undefined leave it off.
// Returns null (off) or all four fields. The ranges are the core's rules,
// checked in bindings.cpp (check_quality_options), except maxPoints.
function checkQuality(quality) {
  if (quality === undefined || quality === null || quality === false) return null;
  if (quality === true) return { ...QUALITY_DEFAULTS };
  const fields = Object.keys(QUALITY_DEFAULTS).join(', ');
  if (typeof quality !== 'object' || Array.isArray(quality)) {
    throw invalidArgument(
      `tetrahedralize: option "quality" must be true or an object with any of ${fields}, got ${describe(quality)}.`,
      '',
    );
  }
  const out = { ...QUALITY_DEFAULTS };
  for (const [key, value] of Object.entries(quality)) {
    if (!Object.hasOwn(QUALITY_DEFAULTS, key)) {
      throw invalidArgument(`tetrahedralize: unknown option "quality.${key}" (known: ${fields}).`, '');
    }
    if (value === undefined) continue;
    if (typeof value !== 'number') {
      throw invalidArgument(`tetrahedralize: option "quality.${key}" must be a number, got ${describe(value)}.`, '');
    }
    out[key] = value;
  }
  if (!Number.isSafeInteger(out.maxPoints) || out.maxPoints < 0) {
    throw invalidArgument(
      `tetrahedralize: option "quality.maxPoints" must be a whole number >= 0 (0: the default limit), got ${out.maxPoints}.`,
      '',
    );
  }
  return out;
}

function typed(value, Type, what, fn) {
  if (value instanceof Type) return value;
  if (Array.isArray(value) || (ArrayBuffer.isView(value) && !(value instanceof DataView))) {
    const out = Type.from(value);
    if (Type !== Float64Array && out.some((x, i) => x !== Number(value[i]))) {
      throw invalidArgument(`${fn}: ${what} must hold non-negative integers.`, '');
    }
    return out;
  }
  throw invalidArgument(`${fn}: ${what} must be a ${Type.name} or an array of numbers, got ${describe(value)}.`, '');
}

// Every accepted input as the one shape bindings.cpp reads (see there):
// {bytes, fileName}, a readPlc() summary, {points, triangles}, or
// {points, facets: [{loops, holes?, marker?}], segments?, holes?, regions?}.
// [{marker, name}] checked, so that the module reads only ints and strings.
function markerNames(names, fn) {
  if (!Array.isArray(names)) throw invalidArgument(`${fn}: markerNames must be an array of {marker, name}.`, '');
  return names.map((n, i) => {
    if (!n || !Number.isInteger(n.marker) || typeof n.name !== 'string') {
      throw invalidArgument(`${fn}: markerNames[${i}] must be {marker: integer, name: string}.`, '');
    }
    return { marker: n.marker, name: n.name };
  });
}

function normalizeInput(input, fn) {
  if (input === null || typeof input !== 'object') {
    throw invalidArgument(`${fn}(input): input must be an object, got ${describe(input)}.`, '');
  }
  if (input[SOURCE]) return { bytes: input[SOURCE].data, fileName: input[SOURCE].fileName };
  if (input.bytes !== undefined) {
    if (typeof input.fileName !== 'string' || input.fileName.length === 0) {
      throw invalidArgument(`${fn}(input): input.fileName must be a non-empty string (it picks the format).`, '');
    }
    const bytes = asBytes(input.bytes);
    if (bytes === null) {
      throw invalidArgument(`${fn}(input): input.bytes must be a Uint8Array, an ArrayBuffer or a Buffer, got ${describe(input.bytes)}.`, input.fileName);
    }
    return { bytes, fileName: input.fileName };
  }
  if (input.points === undefined) {
    throw invalidArgument(`${fn}(input): input needs {bytes, fileName} or {points, triangles | facets}.`, '');
  }
  const out = { fileName: typeof input.fileName === 'string' ? input.fileName : '' };
  out.points = typed(input.points, Float64Array, 'points', fn);
  if (out.points.length % 3 !== 0) throw invalidArgument(`${fn}: points needs 3 numbers per point.`, '');
  if (input.triangles !== undefined) {
    const tri = typed(input.triangles, Uint32Array, 'triangles', fn);
    if (tri.length % 3 !== 0) throw invalidArgument(`${fn}: triangles needs 3 indices per triangle.`, '');
    out.loopVertices = tri;
    out.loopCounts = new Uint32Array(tri.length / 3).fill(1);
    out.loopSizes = new Uint32Array(tri.length / 3).fill(3);
  } else if (Array.isArray(input.facets)) {
    const counts = [], sizes = [], verts = [], holeCounts = [], holePoints = [], markers = [];
    input.facets.forEach((f, i) => {
      if (!f || !Array.isArray(f.loops) || f.loops.length === 0) {
        throw invalidArgument(`${fn}: facets[${i}].loops must be a non-empty array of vertex loops.`, '');
      }
      counts.push(f.loops.length);
      for (const loop of f.loops) {
        const l = typed(loop, Uint32Array, `facets[${i}].loops`, fn);
        sizes.push(l.length);
        for (const v of l) verts.push(v);
      }
      const holes = f.holes ?? [];
      holeCounts.push(holes.length);
      for (const h of holes) holePoints.push(h[0], h[1], h[2]);
      markers.push(f.marker ?? 0);
    });
    out.loopCounts = Uint32Array.from(counts);
    out.loopSizes = Uint32Array.from(sizes);
    out.loopVertices = Uint32Array.from(verts);
    out.holeCounts = Uint32Array.from(holeCounts);
    out.holePoints = Float64Array.from(holePoints);
    out.markers = Int32Array.from(markers);
  } else {
    throw invalidArgument(`${fn}(input): input.points needs input.triangles or input.facets.`, '');
  }
  if (input.markerNames !== undefined) out.markerNames = markerNames(input.markerNames, fn);
  if (input.segments !== undefined) out.segments = typed(input.segments, Uint32Array, 'segments', fn);
  if (input.holes !== undefined) out.holes = typed(input.holes, Float64Array, 'holes', fn);
  if (input.regions !== undefined) {
    if (!Array.isArray(input.regions)) throw invalidArgument(`${fn}: regions must be an array.`, '');
    out.regions = Float64Array.from(
      input.regions.flatMap((r) => [r.point[0], r.point[1], r.point[2], r.attribute ?? 0, r.maxVolume ?? -1]),
    );
  }
  return out;
}

function checkResult(result, fn) {
  if (!result || !(result.points instanceof Float64Array) || !(result.tets instanceof Uint32Array)) {
    throw invalidArgument(`${fn}(result): result must be what tetrahedralize() returned.`, '');
  }
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
    // The two-thread module (Node, node.js) has Emscripten's thread pool.
    threaded: typeof mod.PThread === 'object' && mod.PThread !== null,
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
      return withSource(data, fileName, {
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
      });
    },

    tetrahedralize(input, options) {
      const opts = checkOptions(options);
      const plc = normalizeInput(input, 'tetrahedralize');
      const signal = opts.signal;
      if (signal?.aborted) throw cancelled(plc.fileName);
      const onProgress = opts.onProgress;
      // Called by the core between and inside phases; returning true cancels.
      const progress = (phase, fraction) => {
        if (onProgress) onProgress({ phase, fraction });
        return signal ? signal.aborted : false;
      };
      const raw = call(() =>
        mod._tetrahedralize(
          plc,
          {
            keepConvexHull: opts.keepConvexHull,
            validate: opts.validate,
            checkIntersections: opts.checkIntersections,
            keepTriangles: opts.keepTriangles,
            repair: opts.repair,
            fillHoles: opts.fillHoles,
            unionOfParts: opts.unionOfParts,
            partsAsRegions: opts.partsAsRegions,
            degeneracy: opts.degeneracy,
            verbosity: opts.verbosity,
            stopAfter: opts.stopAfter,
            quality: opts.quality,
          },
          progress,
        ),
      );
      if (!raw.ok) {
        const err = errorFromRaw(raw);
        if (raw.error.facets) err.facets = Array.from(raw.error.facets);
        throw err;
      }
      delete raw.ok;
      raw.validation = opts.validate ? { ok: true, message: '' } : null;
      return raw;
    },

    repair(input, options) {
      const plc = normalizeInput(input, 'repair');
      const opts = checkRepair(options ?? {}, 'repair(input, options): options');
      const raw = call(() => mod._repair(plc, opts.fillHoles, opts.union, opts.partsAsRegions));
      if (!raw.ok) throw errorFromRaw(raw);
      // The repaired PLC in the {points, facets, ...} input shape, so that it
      // can go straight to tetrahedralize().
      const facets = [];
      let loop = 0, vertex = 0, hole = 0;
      for (let f = 0; f < raw.loopCounts.length; f++) {
        const loops = [];
        for (let k = 0; k < raw.loopCounts[f]; k++, loop++) {
          loops.push(Array.from(raw.loopVertices.subarray(vertex, vertex + raw.loopSizes[loop])));
          vertex += raw.loopSizes[loop];
        }
        const holes = [];
        for (let k = 0; k < raw.holeCounts[f]; k++, hole++) holes.push(Array.from(raw.holePoints.subarray(3 * hole, 3 * hole + 3)));
        facets.push({ loops, holes, marker: raw.markers[f] });
      }
      const regions = [];
      for (let i = 0; i + 4 < raw.regions.length; i += 5) {
        const r = raw.regions;
        regions.push({ point: [r[i], r[i + 1], r[i + 2]], attribute: r[i + 3], maxVolume: r[i + 4] });
      }
      return {
        fileName: plc.fileName,
        points: raw.points,
        facets,
        segments: raw.segments,
        holes: raw.holes,
        regions,
        markerNames: raw.markerNames,
        facetSources: raw.facetSources,
        segmentSources: raw.segmentSources,
        report: raw.report,
        poly: raw.poly,
      };
    },

    delaunay(points) {
      const xyz = typed(points, Float64Array, 'points', 'delaunay');
      if (xyz.length % 3 !== 0) throw invalidArgument('delaunay(points): points needs 3 numbers per point.', '');
      const raw = call(() => mod._delaunay(xyz));
      if (!raw.ok) throw errorFromRaw(raw);
      return { tets: raw.tets, stats: { points: xyz.length / 3, tets: raw.tets.length / 4, msDelaunay: raw.msDelaunay } };
    },

    validate(input, result) {
      const plc = normalizeInput(input, 'validate');
      checkResult(result, 'validate');
      const raw = call(() => mod._validate(plc, result));
      return raw.ok ? { ok: true, message: '' } : { ok: false, message: raw.error.message, error: errorFromRaw(raw) };
    },

    write(result, format) {
      checkResult(result, 'write');
      if (!WRITE_FORMATS.includes(format)) {
        throw invalidArgument(
          `write(result, format): format must be one of ${WRITE_FORMATS.join(', ')}, got ${describe(format)}${
            typeof format === 'string' ? ` "${format}"` : ''
          }.`,
          '',
        );
      }
      const raw = call(() => mod._write(format, result));
      if (!raw.ok) throw errorFromRaw(raw);
      // Gmsh and VTU files come back as bytes (msh-binary and vtu hold binary data).
      return raw.bytes ?? raw.text;
    },

    readSurface(bytes, fileName) {
      const plc = normalizeInput({ bytes, fileName }, 'readSurface');
      const raw = call(() => mod._readSurface(plc));
      if (!raw.ok) throw errorFromRaw(raw);
      return {
        points: raw.points,
        triangles: raw.triangles,
        triangleFacets: raw.triangleFacets,
        error: raw.error ? errorFromRaw({ error: raw.error }) : null,
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
