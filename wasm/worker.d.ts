// Types of `cdt3d/worker` (hand-written, like cdt3d.d.ts; checked by
// tests/js/types.test.mjs through tests/js/types-check.mts).
import type { Cdt3dError, InputSurface, MeshResult, Progress, TetrahedralizeOptions } from './cdt3d.js';

/** What a worker job accepts: a file (its name picks the format) or arrays. */
/** A File or Blob (structural, so these types need no DOM library). */
export interface BlobLike {
  arrayBuffer(): Promise<ArrayBuffer>;
  readonly name?: string;
}
/** An AbortSignal (structural). */
export interface AbortSignalLike {
  readonly aborted: boolean;
}

export type WorkerInput =
  | BlobLike
  | ArrayBuffer
  | Uint8Array
  | { points: Float64Array; triangles: Uint32Array };

export interface WorkerJobOptions {
  /** Progress of the job (throttled to about one report per 40 ms or phase change). */
  onProgress?: (progress: Progress) => void;
  /** Aborting terminates the worker; the promise rejects with Cdt3dError "cancelled". */
  signal?: AbortSignalLike;
  /** The file name (picks the format) when `file` is not a File. */
  fileName?: string;
  /** Called with the input surface as soon as it is read. */
  onSurface?: (surface: InputSurface) => void;
  /** Transfer (detach) the input buffer instead of copying it. Default true. */
  transfer?: boolean;
}

/** What `prepare()` did. */
export interface PrepareResult {
  /** The instance runs the two-thread module (cross-origin isolated pages, Node). */
  threaded: boolean;
  /** Milliseconds to start the worker's instance (download, compile, instantiate). */
  loadMs: number;
  /** Milliseconds of each warm-up round run. */
  runs: number[];
}

/** A worker kept alive between jobs (the WebAssembly module is instantiated once). */
export interface MeshWorker {
  mesh(file: WorkerInput, options?: Omit<TetrahedralizeOptions, 'onProgress' | 'signal'>, extra?: WorkerJobOptions): Promise<MeshResult>;
  readSurface(file: WorkerInput, extra?: { fileName?: string; signal?: AbortSignalLike }): Promise<InputSurface>;
  write(result: MeshResult, format: 'node' | 'ele' | 'face' | 'vtk' | 'mesh', extra?: { signal?: AbortSignalLike }): Promise<string>;
  write(result: MeshResult, format: 'msh' | 'msh-binary' | 'vtu', extra?: { signal?: AbortSignalLike }): Promise<Uint8Array>;
  /**
   * Starts the worker and loads the module now (compiled while it
   * downloads), then meshes built-in models `rounds` times (default 4:
   * three small ones, then a large one) with `options`, so that the engine has optimised the hot code before
   * the first real model. Stops early when a real job is submitted.
   */
  prepare(settings?: {
    rounds?: number;
    options?: Omit<TetrahedralizeOptions, 'onProgress' | 'signal'>;
    signal?: AbortSignalLike;
  }): Promise<PrepareResult>;
  /** True while a job runs. */
  readonly busy: boolean;
  /** Stops the worker; pending jobs reject with "cancelled". */
  terminate(): void;
}

export function createMeshWorker(): MeshWorker;

/**
 * Meshes one model in a worker of its own (stopped afterwards). Rejects with a
 * Cdt3dError (with `facets` and `surface` when the error names facets).
 */
export function meshInWorker(
  file: WorkerInput,
  options?: Omit<TetrahedralizeOptions, 'onProgress' | 'signal'>,
  extra?: WorkerJobOptions,
): Promise<MeshResult>;

export type { Cdt3dError };
