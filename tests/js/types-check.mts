// Compiled (never run) by types.test.mjs with `tsc --noEmit --strict`: uses
// every declaration of wasm/cdt3d.d.ts through the package name, and checks
// that misuse is rejected (@ts-expect-error fails the build when no error).
import { createCdt3d, Cdt3dError } from 'cdt3d';
import { createMeshWorker, meshInWorker } from 'cdt3d/worker';
import type { MeshWorker } from 'cdt3d/worker';
import type {
  Bytes,
  Cdt3d,
  Cdt3dErrorCode,
  Cdt3dErrorJSON,
  Cdt3dErrorLocation,
  CreateCdt3dOptions,
  MemoryUsage,
  PlcInfo,
  MeshResult,
  MeshStatistics,
  Phase,
  Progress,
  QualityOptions,
  ValidationResult,
  InputSurface,
  RepairReport,
  RepairResult,
} from 'cdt3d';

const options: CreateCdt3dOptions = {
  wasmBinary: new Uint8Array(8),
  locateFile: (path: string, prefix: string) => prefix + path,
};
const cdt: Cdt3d = await createCdt3d();
await createCdt3d(options);
await createCdt3d({ wasmBinary: new ArrayBuffer(8) });

const version: string = cdt.version;
const codes: readonly Cdt3dErrorCode[] = cdt.errorCodes;

const inputs: Bytes[] = [new Uint8Array(4), new ArrayBuffer(4), new DataView(new ArrayBuffer(4)), new SharedArrayBuffer(4)];
for (const bytes of inputs) {
  const info: PlcInfo = cdt.readPlc(bytes, 'model.off');
  const file: string = info.file;
  const counts: number[] = [
    info.fileVertices, info.points, info.welded, info.unreferenced, info.facets, info.triangles,
    info.loops, info.segments, info.holes, info.regions,
  ];
  const [x, y, z]: [number, number, number] = info.bboxMin;
  const max: readonly number[] = info.bboxMax;
  void [file, counts, x, y, z, max];
}

const memory: MemoryUsage = cdt.memoryUsage();
const heap: number = memory.heapBytes + memory.allocatedBytes;

try {
  cdt.readPlc(new Uint8Array(0), 'empty.stl');
} catch (e) {
  if (e instanceof Cdt3dError) {
    const code: Cdt3dErrorCode = e.code;
    const where: Cdt3dErrorLocation = e;
    const json: Cdt3dErrorJSON = e.toJSON();
    const message: string = e.message;
    const n: number = e.line + e.record + e.facet + e.vertex + e.otherFacet;
    const rebuilt = new Cdt3dError(json.code, json.message, json);
    const base: Error = rebuilt;
    void [code, where, message, n, base, where.file];
  }
}
new Cdt3dError('parse', 'Bad token.');
new Cdt3dError('internal', 'outer', { line: 3, cause: new Error('inner') });

// Meshing: every input form, options, results, validation, writers, surface.
{
  const bytes = new Uint8Array(8);
  const controller = { aborted: false };
  const r: MeshResult = cdt.tetrahedralize({ bytes, fileName: 'a.off' }, {
    keepConvexHull: true,
    validate: true,
    checkIntersections: false,
    keepTriangles: false,
    mergeCoplanarFacets: true,
    degeneracy: 'paper',
    verbosity: 1,
    stopAfter: 'facets',
    signal: controller,
    onProgress: (p: Progress) => {
      const phase: Phase = p.phase;
      void [phase, p.fraction];
    },
  });
  const pts: Float64Array = r.points;
  const tets: Uint32Array = r.tets;
  const kinds: Uint8Array = r.steinerKinds;
  const parents: Int32Array = r.steinerParents;
  const s: MeshStatistics = r.stats;
  const n: number = s.tets + s.steinerSegment + s.msTotal + s.radiusEdgeHistogram[0] + r.inputPoints +
    s.missingSegments + s.facetSplits + s.flatFlips + s.flatTets;
  const fromInfo = cdt.tetrahedralize(cdt.readPlc(bytes, 'a.off'));
  const fromTriangles = cdt.tetrahedralize({ points: [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1], triangles: [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3] });
  const fromFacets = cdt.tetrahedralize({
    points: new Float64Array(12),
    facets: [{ loops: [[0, 1, 2]], holes: [[0, 0, 0]], marker: 2 }],
    segments: [0, 3],
    holes: [0.1, 0.1, 0.1],
    regions: [{ point: [0.2, 0.2, 0.2], attribute: 1, maxVolume: -1 }],
  });
  const d = cdt.delaunay(new Float64Array(12));
  const dt: Uint32Array = d.tets;
  void [dt, d.stats.msDelaunay];
  const v: ValidationResult = cdt.validate({ bytes, fileName: 'a.off' }, fromInfo);
  const ok: boolean = v.ok;
  const text: string = cdt.write(fromTriangles, 'vtk');
  const msh: Uint8Array = cdt.write(fromTriangles, 'msh-binary');
  const vtu: Uint8Array = cdt.write(fromTriangles, 'vtu');
  // @ts-expect-error the Gmsh file is bytes
  const mshText: string = cdt.write(fromTriangles, 'msh');
  const surface: InputSurface = cdt.readSurface(bytes, 'a.off');
  const tris: Uint32Array = surface.triangles;
  const err: Cdt3dError | null = surface.error;
  void [pts, tets, kinds, parents, n, fromFacets, ok, text, msh, vtu, mshText, tris, err, r.validation];
  // @ts-expect-error unknown format
  cdt.write(r, 'stl');
  // @ts-expect-error stopAfter is a phase
  cdt.tetrahedralize({ bytes, fileName: 'a.off' }, { stopAfter: 'later' });
}

// The worker helper.
{
  const w: MeshWorker = createMeshWorker();
  const job: Promise<MeshResult> = w.mesh(new Uint8Array(4), { keepConvexHull: true }, {
    fileName: 'a.stl',
    onProgress: (p: Progress) => void p.fraction,
    signal: { aborted: false },
  });
  const once: Promise<MeshResult> = meshInWorker({ points: new Float64Array(12), triangles: new Uint32Array(12) });
  const text: Promise<string> = w.write(await job, 'mesh');
  const vtu: Promise<Uint8Array> = w.write(await job, 'vtu');
  const busy: boolean = w.busy;
  const prepared = await w.prepare({ rounds: 2, options: { validate: true } });
  const warm: [boolean, number, number[]] = [prepared.threaded, prepared.loadMs, prepared.runs];
  // @ts-expect-error rounds is a number
  void w.prepare({ rounds: 'many' });
  void warm;
  w.terminate();
  void [once, text, vtu, busy];
}

// Misuse the declarations must reject.
// @ts-expect-error bytes must be binary data
cdt.readPlc('solid x', 'x.stl');
// @ts-expect-error the file name is required
cdt.readPlc(new Uint8Array(4));
// @ts-expect-error the file name is a string
cdt.readPlc(new Uint8Array(4), 3);
// @ts-expect-error not an error code
new Cdt3dError('no-such-code', 'x');
// @ts-expect-error version is read-only
cdt.version = '1';
// @ts-expect-error no such field
cdt.readPlc(new Uint8Array(4), 'a.off').tetrahedra;
// @ts-expect-error wasmBinary is bytes
await createCdt3d({ wasmBinary: 'cdt3d.wasm' });
// @ts-expect-error createCdt3d is async
const notYet: Cdt3d = createCdt3d();

void [version, codes, heap, notYet];

// Repair: a repaired PLC goes straight back into tetrahedralize.
const repaired: RepairResult = cdt.repair({ bytes: new Uint8Array(4), fileName: 'model.off' });
const report: RepairReport = repaired.report;
const repairCounts: number[] = [report.weldedPoints, report.duplicateFacets, report.tjunctionVertices,
  report.crossingPairs, report.unresolvedPairs, repaired.facetSources[0]];
const changedFacets: Uint32Array = report.changedFacets;
const fromRepaired: MeshResult = cdt.tetrahedralize(repaired, { repair: false });
const meshReport: RepairReport | undefined = cdt.tetrahedralize({ bytes: new Uint8Array(4), fileName: 'a.obj' }, { repair: true }).repair;
const polyText: string = repaired.poly;
const regionParts: number[][] | undefined = cdt.tetrahedralize(repaired, { repair: { partsAsRegions: true } }).repair?.regionParts;
const parts: number = report.parts + report.regionParts.length;
void [regionParts, parts];
// @ts-expect-error repair is a boolean option
cdt.tetrahedralize(repaired, { repair: 'yes' });
void [repairCounts, changedFacets, fromRepaired, meshReport, polyText, report.changed];

// Quality refinement: the options, the "refine" phase, the new statistics.
{
  const bytes = new Uint8Array(4);
  const q: QualityOptions = { radiusEdge: 1.414, maxVolume: 0.5, minDihedral: 15, maxPoints: 1000 };
  const refined: MeshResult = cdt.tetrahedralize({ bytes, fileName: 'a.off' }, { quality: q });
  cdt.tetrahedralize({ bytes, fileName: 'a.off' }, { quality: true, stopAfter: 'refine' });
  cdt.tetrahedralize({ bytes, fileName: 'a.off' }, { quality: {} });
  const s: MeshStatistics = refined.stats;
  const added: number = s.refineSegment + s.refineFacet + s.refineVolume + s.refineSkipped + s.refineCapped +
    s.improveFlips + s.improveSmooths + s.improvePoints + s.msRefine + s.minDihedralBefore;
  const delaunay: boolean = refined.delaunay;
  void delaunay;
  const histograms: number[][] = [s.dihedralHistogram, s.radiusEdgeHistogramBefore, s.dihedralHistogramBefore];
  const phase: Phase = 'refine';
  const inWorker: Promise<MeshResult> = meshInWorker(bytes, { quality: { maxVolume: 1 } }, { fileName: 'a.off' });
  void [added, histograms, phase, inWorker];
  // @ts-expect-error the quality fields are numbers
  cdt.tetrahedralize({ bytes, fileName: 'a.off' }, { quality: { radiusEdge: '2' } });
  // @ts-expect-error no such quality field
  cdt.tetrahedralize({ bytes, fileName: 'a.off' }, { quality: { ratio: 2 } });
  // @ts-expect-error quality is an object or a boolean
  cdt.tetrahedralize({ bytes, fileName: 'a.off' }, { quality: 2 });
}
