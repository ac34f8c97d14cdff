// Types of the cdt3d package (hand-written: Debian's emscripten 3.1.6 has no
// --embind-emit-tsd). Checked by tests/js/types.test.mjs.

/** Stable error codes (the core's error_code_name), also printed by the native CLI. */
export type Cdt3dErrorCode =
  | 'io'
  | 'unknown-format'
  | 'empty'
  | 'truncated'
  | 'parse'
  | 'nan'
  | 'coordinate-range'
  | 'index'
  | 'degenerate'
  | 'nonplanar'
  | 'duplicate'
  | 'too-large'
  | 'coplanar'
  | 'collinear'
  | 'too-few-points'
  | 'invalid-argument'
  | 'cancelled'
  | 'out-of-memory'
  | 'internal'
  | 'limit'
  | 'invalid-plc';

/** Where an error happened. Fields that do not apply are -1 (file: ''). */
export interface Cdt3dErrorLocation {
  /** Input file name, '' if none. */
  file: string;
  /** 1-based text line. */
  line: number;
  /** 0-based binary record (e.g. STL triangle). */
  record: number;
  /** 0-based facet index. */
  facet: number;
  /** 0-based vertex index. */
  vertex: number;
  /** Second facet (duplicates, intersections). */
  otherFacet: number;
}

/** The plain-object form of a Cdt3dError: the native CLI's `--json` "error" object. */
export interface Cdt3dErrorJSON extends Cdt3dErrorLocation {
  code: Cdt3dErrorCode;
  message: string;
}

/** Every error thrown by cdt3d; same fields and values as the native CLI's errors. */
export class Cdt3dError extends Error implements Cdt3dErrorJSON {
  /**
   * Builds an error, e.g. from a {@link Cdt3dErrorJSON} posted by a worker:
   * `new Cdt3dError(e.code, e.message, e)`. Missing location fields become -1.
   */
  constructor(
    code: Cdt3dErrorCode,
    message: string,
    where?: Partial<Cdt3dErrorLocation> & { cause?: unknown },
  );
  code: Cdt3dErrorCode;
  file: string;
  line: number;
  record: number;
  facet: number;
  vertex: number;
  otherFacet: number;
  /** Plain object with the fields above (Error properties do not survive postMessage). */
  toJSON(): Cdt3dErrorJSON;
}

/** Summary of a piecewise linear complex; the fields of `cdt3d info MODEL --json`. */
export interface PlcInfo {
  /** The file name given to readPlc. */
  file: string;
  /** Vertex records in the file, before welding. */
  fileVertices: number;
  /** Distinct points after exact welding (identical coordinates only). */
  points: number;
  /** File vertex records merged into an identical earlier point. */
  welded: number;
  /** Points used by no facet or segment. */
  unreferenced: number;
  facets: number;
  /** Triangles after fan-triangulating each loop. */
  triangles: number;
  /** Polygon loops of all facets. */
  loops: number;
  /** Explicit segments plus distinct facet boundary edges. */
  segments: number;
  /** Volume hole points. */
  holes: number;
  /** Region points. */
  regions: number;
  bboxMin: [number, number, number];
  bboxMax: [number, number, number];
}

/** Memory of one cdt3d instance. */
export interface MemoryUsage {
  /** Size of the WebAssembly memory (it grows, never shrinks; at most 4 GiB). */
  heapBytes: number;
  /** Bytes currently allocated inside it. */
  allocatedBytes: number;
}

/** Input file contents. Views are read in place (byteOffset/byteLength honoured). */
export type Bytes = Uint8Array | ArrayBuffer | SharedArrayBuffer | ArrayBufferView;

/** One instance of the WebAssembly module. Calls are synchronous; use a worker for big inputs. */
export interface Cdt3d {
  /** Version of the compiled core, e.g. "0.1.0". */
  readonly version: string;
  /** Every code a Cdt3dError can carry. */
  readonly errorCodes: readonly Cdt3dErrorCode[];
  /**
   * Parses a PLC (.stl ASCII/binary, .off, .obj, .ply, .poly, .smesh) and
   * checks it. `fileName` picks the format by extension and names the file in
   * errors.
   * @throws {Cdt3dError} on invalid input ("invalid-argument" for bad arguments).
   */
  readPlc(bytes: Bytes, fileName: string): PlcInfo;
  /** Current memory use of this instance. */
  memoryUsage(): MemoryUsage;
}

export interface CreateCdt3dOptions {
  /** The .wasm bytes, when the caller has them already (skips the fetch/read). */
  wasmBinary?: ArrayBuffer | Uint8Array;
  /** Where to fetch `path` ("cdt3d.wasm") from; `prefix` is the script's folder. */
  locateFile?: (path: string, prefix: string) => string;
}

/**
 * Loads and instantiates the WebAssembly module. Each call creates an
 * independent instance with its own memory.
 * @throws {Cdt3dError} "invalid-argument" for bad options, "io"/"internal" if
 * the module cannot be loaded.
 */
export function createCdt3d(options?: CreateCdt3dOptions): Promise<Cdt3d>;
