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
  | 'invalid-plc'
  | 'self-intersection'
  | 'open-boundary';

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
  /** 0-based segment index (explicit segments, then facet edges, sorted). */
  segment: number;
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
  segment: number;
  /** For "self-intersection": every intersecting pair of facets, flattened [a0, b0, a1, b1, ...]. */
  facets?: number[];
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
   * True for the two-thread module that Node, and cross-origin isolated
   * pages and their workers, get by default: a call then does some of its
   * work (the self-intersection test, half of the later insertion rounds of
   * step 1 from 20,000 points, half of the facet triangulations and
   * statistics) on a second core. False on pages that are not cross-origin
   * isolated, and with `createCdt3d({ threads: false })`.
   */
  readonly threaded: boolean;
  /**
   * Parses a PLC (.stl ASCII/binary, .off, .obj, .ply, .poly, .smesh) and
   * checks it. `fileName` picks the format by extension and names the file in
   * errors.
   * @throws {Cdt3dError} on invalid input ("invalid-argument" for bad arguments).
   */
  readPlc(bytes: Bytes, fileName: string): PlcInfo;
  /**
   * The constrained Delaunay tetrahedralization of a PLC (Si & Gärtner 2005),
   * with the exterior and holes carved away. Synchronous: progress callbacks
   * fire during the call; `signal` is checked at each progress report.
   * @throws {Cdt3dError} bad input (with where), "cancelled", "out-of-memory", "invalid-argument".
   */
  tetrahedralize(input: PlcInput, options?: TetrahedralizeOptions): MeshResult;
  /**
   * Repairs a PLC exactly (the native `cdt3d repair`): welds identical points;
   * drops repeated vertices, zero-area polygons and duplicate facets; splits
   * non-planar facets into triangles; makes T-junction vertices vertices of
   * the facets they lie on; inserts the intersection segments of crossing
   * facets (new points rounded to doubles, checked again exactly). The input
   * is not checked first (that is what repair is for). The result is a
   * {@link PlcInput} for tetrahedralize(). With `fillHoles`, every boundary
   * loop of an open surface is first closed by triangles of its vertices.
   * Parts that crossed become their union (`union: false` keeps every cell).
   * With `partsAsRegions` the report lists the regions (`regionParts`), but
   * the returned PLC carries no region points: to get the labelled tets,
   * mesh with `tetrahedralize(input, { repair: { partsAsRegions: true } })`.
   * @throws {Cdt3dError} what repair cannot fix (e.g. "nan", or "self-intersection"
   *   naming input facets that still intersect).
   */
  repair(input: PlcInput, options?: RepairOptions): RepairResult;
  /** Step 1 alone: the Delaunay tetrahedralization of a point set (3 coordinates per point). */
  delaunay(points: Float64Array | number[]): { tets: Uint32Array; stats: { points: number; tets: number; msDelaunay: number } };
  /** Checks a result against its input with exact predicates (valid, facets recovered, constrained Delaunay). */
  validate(input: PlcInput, result: MeshResult): ValidationResult;
  /** A result as a text file: TetGen .node/.ele/.face (numbered from 0), legacy VTK, or Medit .mesh. */
  write(result: MeshResult, format: 'node' | 'ele' | 'face' | 'vtk' | 'mesh'): string;
  /**
   * A result as the bytes of a file: Gmsh MSH 4.1 ('msh' ASCII, 'msh-binary'; regions
   * and facet markers as physical groups) or VTK XML .vtu ('vtu': cell data region and
   * min_dihedral, point data steiner_kind), the same bytes as the native CLI's.
   */
  write(result: MeshResult, format: 'msh' | 'msh-binary' | 'vtu'): Uint8Array;
  /**
   * The input surface as triangles, for display. Files that fail their checks
   * still give what could be read, with the error in `error`.
   */
  readSurface(bytes: Bytes, fileName: string): InputSurface;
  /** Current memory use of this instance. */
  memoryUsage(): MemoryUsage;
}

/** A polygon facet: loops of point indices in one plane; `holes`: points inside facet holes. */
export interface FacetInput {
  loops: ArrayLike<number>[];
  holes?: [number, number, number][];
  marker?: number;
}

/** A region point: the tets of its region get `attribute`. */
export interface RegionInput {
  point: [number, number, number];
  attribute?: number;
  maxVolume?: number;
}

/** A name the input gives a facet marker (an OBJ group, an ASCII STL solid). */
export interface MarkerName {
  marker: number;
  name: string;
}

/** What tetrahedralize and validate accept. */
export type PlcInput =
  | { bytes: Bytes; fileName: string }
  | PlcInfo
  | {
      points: Float64Array | number[];
      triangles: Uint32Array | number[];
      segments?: Uint32Array | number[];
      holes?: Float64Array | number[];
      regions?: RegionInput[];
      /** Names of facet markers (Gmsh physical names in 'msh' output). */
      markerNames?: MarkerName[];
      fileName?: string;
    }
  | {
      points: Float64Array | number[];
      facets: FacetInput[];
      segments?: Uint32Array | number[];
      holes?: Float64Array | number[];
      regions?: RegionInput[];
      /** Names of facet markers (Gmsh physical names in 'msh' output). */
      markerNames?: MarkerName[];
      fileName?: string;
    };

/** The phases in order; "refine" runs only with the `quality` option. */
export type Phase = 'read' | 'delaunay' | 'segments' | 'degeneracy' | 'facets' | 'carve' | 'refine' | 'done';

export interface Progress {
  phase: Phase;
  /** Overall fraction of the run in [0, 1]; reaches 1 at phase "done". */
  fraction: number;
}

/**
 * Quality refinement of the CDT (constrained Delaunay refinement: encroached
 * subsegments and subfaces split, circumcentres of bad tets inserted; the
 * result is still a CDT of the refined PLC). The native CLI's `--quality
 * [RATIO]`, `--max-volume V`, `--min-dihedral D`, `--max-points N`. Bad
 * values throw Cdt3dError "invalid-argument" naming the field.
 */
export interface QualityOptions {
  /** Bound on circumradius / shortest edge of every tet, >= 1 (tetgen -q). Default 2. */
  radiusEdge?: number;
  /** Largest tet volume, > 0 (tetgen -a); -1: none (default). Regions' maxVolume applies too. */
  maxVolume?: number;
  /**
   * Afterwards raise the smallest dihedral angle towards this many degrees
   * (0-70) by flips, vertex moves and, where neither helps, a few new points
   * inside the volume (like tetgen -O). Default 15; 0: no such pass. The
   * result then covers every facet and segment but is no longer Delaunay
   * (`MeshResult.delaunay` false); with 0 it stays a CDT.
   */
  minDihedral?: number;
  /** Stop refining after this many added points (stats.refineCapped is then 1). Default 0: the core's limit. */
  maxPoints?: number;
}

export interface TetrahedralizeOptions {
  /** Keep the tets between the PLC and its convex hull (tetgen -c). Default false. */
  keepConvexHull?: boolean;
  /** Validate the result (throws "internal" if it fails). Default false. */
  validate?: boolean;
  /** Reject self-intersecting input (exact). Default true. */
  checkIntersections?: boolean;
  /**
   * Keep every input facet (triangle) as a facet of its own, like `tetgen -pM`.
   * Default false: flat faces are merged first (facets joined by exactly
   * coplanar edges form one facet whose inner edges are no constraints, like
   * `tetgen -p`); `faceFacets` then name the smallest input facet of each flat face.
   */
  keepTriangles?: boolean;
  /** Old name of the default: `false` means `keepTriangles: true`. */
  mergeCoplanarFacets?: boolean;
  /**
   * Repair the PLC first (as {@link Cdt3d.repair}); the result's faceFacets,
   * steinerParents and errors still name input facets, and `repair` says what
   * changed. `{ fillHoles: true }` also closes the holes of an open surface
   * (`cdt3d mesh --fill-holes`), `{ union: false }` meshes every cell of
   * crossing parts instead of their union (`cdt3d mesh --keep-inner`),
   * `{ partsAsRegions: true }` gives every part a region of its own
   * (`tetAttributes`, `cdt3d mesh --parts-as-regions`).
   * Default false (no repair).
   */
  repair?: boolean | RepairOptions;
  /**
   * How step 3 (local degeneracies: five co-spherical vertices) is handled.
   * "symbolic" (default): symbolic perturbation, no vertex moves and no point
   * is added. "paper": Si & Gärtner §6 as published (perturbations, break
   * points, boundary protection; the native CLI's --paper-degeneracy).
   */
  degeneracy?: 'symbolic' | 'paper';
  /** 0 quiet (default), 1 or 2. */
  verbosity?: number;
  /** Stop after a phase and return all tets reached so far (debugging). Default "done". */
  stopAfter?: Exclude<Phase, 'read'>;
  /**
   * Quality refinement after carving: an object (the fields it leaves out at
   * their defaults) or `true` (all defaults) turns it on; false or absent: off
   * (default).
   */
  quality?: boolean | QualityOptions;
  onProgress?: (progress: Progress) => void;
  /** An AbortSignal: aborting cancels the run at its next progress report with a Cdt3dError "cancelled". */
  signal?: { readonly aborted: boolean };
}

/** Counters, times and quality of a run; the fields of the native CLI's `mesh --json`. */
export interface MeshStatistics {
  /** Points of the input PLC. */
  inputPoints: number;
  /** Facets of the input PLC. */
  inputFacets: number;
  /** Input segments: explicit segments plus distinct facet boundary edges. */
  inputSegments: number;
  /** Points of the mesh (input points plus Steiner points). */
  points: number;
  /** Tetrahedra of the mesh. */
  tets: number;
  /** Constrained faces (the input facets, subdivided). */
  faces: number;
  /** Steiner points on input segments. */
  steinerSegment: number;
  /** Steiner points inside input facets (includes `facetSplits`). */
  steinerFacet: number;
  /** Steiner points in the volume. */
  steinerVolume: number;
  /** Segment recovery (§5): splits by rule 1. */
  rule1: number;
  /** Segment recovery (§5): splits by rule 2. */
  rule2: number;
  /** Segment recovery (§5): splits by rule 3. */
  rule3: number;
  /** Input segments missing from the initial Delaunay tetrahedralization (step 1). */
  missingSegments: number;
  /** Segment recovery (§5): splits of segments acute at both ends. */
  acuteBoth: number;
  /**
   * Segment recovery, default splits (rules 1-3 are used only with
   * degeneracy "paper", or on a segment after 64 splits): splits at the
   * projection of the reference point onto the subsegment, or at its
   * midpoint when that projection lies in its outer fifths.
   */
  splitProjection: number;
  /** Segment recovery, default splits: on the sphere around an endpoint shared with the reference point's segment (a protecting ball, §5). */
  splitShell: number;
  /** Segment recovery: split points removed again because later splits made them redundant (not in steinerSegment). */
  splitRemoved: number;
  /** Most Steiner points on one input segment. */
  maxSplits: number;
  /** Step 3 in "paper" mode: perturbed vertices (0 with the default symbolic perturbation). */
  perturbations: number;
  /** Step 3 in "paper" mode: break points (0 with the default symbolic perturbation). */
  breakPoints: number;
  /** Step 3 in "paper" mode: points protecting segments (0 with the default symbolic perturbation). */
  protectSegment: number;
  /** Step 3 in "paper" mode: points protecting facets (0 with the default symbolic perturbation). */
  protectFacet: number;
  /** Flat edges found (two exactly coplanar facets on opposite sides); 0 with keepTriangles. */
  flatEdges: number;
  /** Facets of the merged PLC made of two or more input facets; 0 with keepTriangles. */
  mergedFacets: number;
  /** Facet recovery (§7): subfaces missing from the mesh when facet recovery starts. */
  missingSubfaces: number;
  /** Facet recovery (§7): missing regions recovered. */
  regions: number;
  /** Facet recovery (§7): cavities retetrahedralized (usually two per region). */
  cavities: number;
  /** Facet recovery (§7): most faces of one cavity. */
  largestCavity: number;
  /** Facet recovery (§7): regions recovered by a fallback (gift-wrapping in a cavity, or a retry). */
  fallbacks: number;
  /**
   * Facet recovery (§7): Steiner points inserted inside a facet because a
   * missing region could not be recovered otherwise (counted in `steinerFacet` too).
   */
  facetSplits: number;
  /** Quality refinement: points added on input segments (counted in `steinerSegment` too). */
  refineSegment: number;
  /** Quality refinement: points added inside input facets (counted in `steinerFacet` too). */
  refineFacet: number;
  /** Quality refinement: points added in the volume, circumcentres of bad tets (counted in `steinerVolume` too). */
  refineVolume: number;
  /**
   * Quality refinement: bad tets it left (before the improvement pass), where every fix
   * would have put a point too close to others, encroached upon a constraint it could not
   * split (with the improvement pass on, a side of a facet corner below 10 degrees is not
   * split), or made a flat tet: near small input angles and thin features.
   * `radiusEdgeHistogram` counts what is left after the pass.
   */
  refineSkipped: number;
  /**
   * Of `refineSkipped`, the tets left on purpose at a facet corner of 10 to 60 degrees:
   * their shortest edge joins the corner's two sides at about the same distance from it,
   * so a point that fixes one makes a shorter edge across the corner.
   */
  refineSmallAngle: number;
  /** 1 when quality.maxPoints stopped the refinement, else 0. */
  refineCapped: number;
  /** Improvement pass (quality.minDihedral): flips made. */
  improveFlips: number;
  /** Improvement pass (quality.minDihedral): vertices moved. */
  improveSmooths: number;
  /** Improvement pass (quality.minDihedral): points added inside the volume (counted in `steinerVolume` too). */
  improvePoints: number;
  /** Milliseconds per phase (msRead: reading and input checks; msRefine: 0 without `quality`). */
  msRead: number;
  /** Step 1: the Delaunay tetrahedralization D0. */
  msDelaunay: number;
  msSegments: number;
  /** Step 3: with the symbolic perturbation, the search for its vertex order (run before step 1). */
  msDegeneracy: number;
  msFacets: number;
  msCarve: number;
  msRefine: number;
  msTotal: number;
  /** Numerically flat tets removed by flips before output. */
  flatFlips: number;
  /**
   * With `keepConvexHull`: numerically flat tets on the hull that no flip
   * removed, left out of the output (slivers of numerically no volume).
   */
  flatPeeled: number;
  /**
   * Output tets that are numerically flat: 6V computed in doubles below
   * 1e-12 × (longest edge)³. 0 on success.
   */
  flatTets: number;
  /** Smallest dihedral angle of the output tets, degrees. */
  minDihedral: number;
  /** Largest dihedral angle of the output tets, degrees. */
  maxDihedral: number;
  /** Tets per radius-edge ratio bin: <1, 1-1.5, 1.5-2, 2-3, 3-5, 5-10, 10-20, 20-50, 50-100, >100. */
  radiusEdgeHistogram: number[];
  /** Tets per bin of their smallest dihedral angle, degrees: <1, 1-5, 5-10, 10-15, 15-20, 20-30, 30-40, 40-50, 50-60, >60. */
  dihedralHistogram: number[];
  /** `minDihedral` of the CDT before quality refinement (equal to `minDihedral` without it). */
  minDihedralBefore: number;
  /** `radiusEdgeHistogram` of the CDT before quality refinement (equal to it without refinement). */
  radiusEdgeHistogramBefore: number[];
  /** `dihedralHistogram` of the CDT before quality refinement (equal to it without refinement). */
  dihedralHistogramBefore: number[];
}

/** A CDT. Arrays are copies (they never detach). Point i < inputPoints is input point i. */
export interface MeshResult {
  /** 3 coordinates per point. */
  points: Float64Array;
  /** 4 point ids per tet, positively oriented. */
  tets: Uint32Array;
  /** 3 point ids per constrained face (the input facets, subdivided). */
  faces: Uint32Array;
  /** Input facet per face (with flat faces merged: the smallest input facet of its flat face). */
  faceFacets: Uint32Array;
  /** Input facet marker per face. */
  faceMarkers: Int32Array;
  /** Names of markers from the input (OBJ groups, ASCII STL solids); write(…, 'msh') uses them. */
  markerNames: MarkerName[];
  /** Region attribute per tet. */
  tetAttributes: Float64Array;
  /** Subsegments of the input segments, 2 point ids each. */
  edges: Uint32Array;
  /** Input segment per edge. */
  edgeSegments: Uint32Array;
  inputPoints: number;
  /** Per Steiner point (index - inputPoints): 1 on a segment, 2 in a facet, 3 in the volume. */
  steinerKinds: Uint8Array;
  /** Per Steiner point: its input segment or facet, -1 for volume points. */
  steinerParents: Int32Array;
  /**
   * True for a constrained Delaunay tetrahedralization. False when the improvement pass
   * (`quality.minDihedral`) flipped tets or moved points: every facet and segment is still
   * covered, but faces need not be locally Delaunay, and validate() does not check that.
   */
  delaunay: boolean;
  /**
   * True when flat faces were merged (the default; false with `keepTriangles`): the mesh is a
   * CDT of the merged PLC, `faceFacets` name the smallest input facet of each flat face, and
   * validate() merges as the run did.
   */
  flatFacesMerged: boolean;
  /**
   * Per input facet (with flat faces merged): the smallest input facet of its flat face, the id
   * `faceFacets` uses; empty with `keepTriangles`.
   */
  flatFaceOf: Uint32Array;
  stats: MeshStatistics;
  /** {ok: true} when options.validate was set (a failed validation throws), else null. */
  validation: ValidationResult | null;
  /** With options.repair: what repair changed. */
  repair?: RepairReport;
}

/** Options of repair. */
export interface RepairOptions {
  /** Close every boundary loop with triangles of its vertices, of least total area. Default false. */
  fillHoles?: boolean;
  /**
   * Where parts cross, the domain is their union: the cells of winding
   * number >= 1 of the surfaces (normals outwards by the right-hand rule; a
   * part with inward normals is a hole in the others, a model with all
   * normals inwards counts as turned inside out); the facets inside it are
   * dropped. Where the facets do not close up consistently every facet is
   * kept (report.unionSkipped). Default true; false meshes every cell of the
   * arrangement, bounded by internal facets (`cdt3d repair --keep-inner`).
   */
  union?: boolean;
  /**
   * Every part a region of its own (`cdt3d mesh --parts-as-regions`): the
   * domain is still the union, but the facets between parts stay as
   * internal facets and tetrahedralize() gives every tet the region
   * attribute of the parts it lies in (`tetAttributes`). A part is a
   * connected component of the input surface (facets joined across shared
   * edges once identical points are welded), numbered by its first facet;
   * attribute p + 1 is where part p alone lies, and each overlap of two or
   * more parts is a region after those (report.regionParts lists them).
   * Tets outside the union (the hull with keepConvexHull, a cavity bounded
   * by inward normals) get 0. Cannot go with `union: false`. Default false.
   */
  partsAsRegions?: boolean;
}

/** What repair changed, step by step (the native `cdt3d repair --json` "repair" object). */
export interface RepairReport {
  /** False when the PLC was valid already: then nothing was changed. */
  changed: boolean;
  inputPoints: number;
  points: number;
  inputFacets: number;
  facets: number;
  /** Step 1: points merged into an identical earlier point. */
  weldedPoints: number;
  /** Step 1: repeated polygon vertices dropped (or cut at). */
  repeatedVertices: number;
  /**
   * With fillHoles: boundary loops closed, the triangles that close them, the
   * points added inside non-planar holes (the patch refined to the size of
   * the triangles around it), loops left open.
   */
  filledHoles: number;
  fillTriangles: number;
  fillPoints: number;
  unfilledHoles: number;
  /** Step 1: polygons of zero area dropped. */
  zeroAreaPolygons: number;
  /** Step 1: facets dropped because no polygon with area was left. */
  degenerateFacets: number;
  /** Step 1: facets dropped as repeats of an earlier facet. */
  duplicateFacets: number;
  /** Step 2: non-planar facets split into triangles. */
  nonplanarFacets: number;
  /** Step 3: (vertex, facet) T-junctions made explicit, and the facets concerned. */
  tjunctionVertices: number;
  tjunctionFacets: number;
  /** Step 4: facet pairs found crossing, facets split, new (rounded) points, rounds. */
  crossingPairs: number;
  crossingFacets: number;
  intersectionPoints: number;
  rounds: number;
  /** Pairs (facets, explicit segments) still intersecting (0 on success). */
  unresolvedPairs: number;
  /** Step 4: explicit segments found crossing or touching a facet or another segment (first round). */
  crossingSegments: number;
  /** Step 4: pieces the explicit segments were split into, beyond one per segment (segmentSources names each piece's input segment). */
  segmentSplits: number;
  /** Step 5: facets dropped as inside the union of crossing parts (or outside every part). */
  innerFacets: number;
  /** Step 5: true when crossings were resolved but the union was not formed (the facets, oriented like their input facets, do not close up); every facet is kept. */
  unionSkipped: boolean;
  /** Step 5, where the union was not formed: facets with the outside of the model on both sides (fins, sheets beside it) dropped; they bound no volume. */
  outsideFacets: number;
  ms: number;
  /** With partsAsRegions (unless the union was skipped): parts found, connected components of the input surface; else 0. */
  parts: number;
  /**
   * With partsAsRegions: entry a - 1 lists the parts (0-based) of region
   * attribute a: [p] for part p alone (empty when no cell is part p's alone),
   * then the overlaps, e.g. [[0], [1], [0, 1]]; else empty.
   */
  regionParts: number[][];
  /** Input facets some step changed (for highlighting). */
  changedFacets: Uint32Array;
}

/** A repaired PLC: a {@link PlcInput} for tetrahedralize(), with what changed. */
export interface RepairResult {
  fileName: string;
  points: Float64Array;
  facets: { loops: number[][]; holes: [number, number, number][]; marker: number }[];
  segments: Uint32Array;
  holes: Float64Array;
  regions: RegionInput[];
  markerNames: MarkerName[];
  /** Per facet of the result: the input facet it comes from. */
  facetSources: Uint32Array;
  /** Per explicit segment of the result: the input segment it is a piece of. */
  segmentSources: Uint32Array;
  report: RepairReport;
  /** The repaired PLC as a TetGen .poly file (what `cdt3d repair -o` writes). */
  poly: string;
}

export interface ValidationResult {
  ok: boolean;
  message: string;
  error?: Cdt3dError;
}

export interface InputSurface {
  points: Float64Array;
  /** 3 point ids per triangle. */
  triangles: Uint32Array;
  /** Input facet per triangle. */
  triangleFacets: Uint32Array;
  /** Why the file is not a valid PLC, if it is not (the surface is still given). */
  error: Cdt3dError | null;
}

export interface CreateCdt3dOptions {
  /** The .wasm bytes, when the caller has them already (skips the fetch/read). */
  wasmBinary?: ArrayBuffer | Uint8Array;
  /** Where to fetch `path` ("cdt3d.wasm") from; `prefix` is the script's folder. */
  locateFile?: (path: string, prefix: string) => string;
  /**
   * False loads the single-threaded module. By default Node, and pages that
   * are cross-origin isolated (and their workers), get the two-thread module
   * (one extra worker thread, started with the instance) unless `wasmBinary`
   * or `locateFile` is given, which name the single-threaded module's .wasm.
   * Elsewhere in browsers true cannot apply (no SharedArrayBuffer).
   */
  threads?: boolean;
}

/**
 * Loads and instantiates the WebAssembly module. Each call creates an
 * independent instance with its own memory.
 * @throws {Cdt3dError} "invalid-argument" for bad options, "io"/"internal" if
 * the module cannot be loaded.
 */
export function createCdt3d(options?: CreateCdt3dOptions): Promise<Cdt3d>;
