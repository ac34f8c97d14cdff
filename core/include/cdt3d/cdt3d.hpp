// cdt3d: constrained Delaunay tetrahedralization of piecewise linear complexes
// (Si & Gärtner, IMR 2005). This header is the whole public API.
//
// The library never throws and never exits: every entry point returns a Status
// whose Error says what went wrong and where (file, line or record, facet,
// vertex).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace cdt3d {

using VertexId = uint32_t;
inline constexpr uint32_t kNone = 0xffffffffu;

/// Largest coordinate magnitude accepted. Keeps every intermediate of the exact
/// predicates (up to degree-5 products of coordinate differences) far from
/// double overflow and underflow. Inputs outside [-kMaxCoordinate,
/// kMaxCoordinate] are rejected with ErrorCode::CoordinateRange.
inline constexpr double kMaxCoordinate = 1e50;

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

/// Every failure the library can report. The stable string form (error_code_name)
/// is what the JS API exposes as `Cdt3dError.code`.
enum class ErrorCode {
  Ok = 0,
  IoError,           ///< "io": file cannot be opened or read
  UnknownFormat,     ///< "unknown-format": extension or content not recognised
  Empty,             ///< "empty": file has no data
  Truncated,         ///< "truncated": file ends early / sizes disagree
  Parse,             ///< "parse": malformed syntax, bad number, bad header
  NonFinite,         ///< "nan": NaN or infinite coordinate
  CoordinateRange,   ///< "coordinate-range": |coordinate| > kMaxCoordinate
  IndexOutOfRange,   ///< "index": vertex index outside the point list
  DegenerateFacet,   ///< "degenerate": < 3 distinct vertices, repeated vertex, zero area
  NonPlanarFacet,    ///< "nonplanar": polygon vertices not coplanar
  DuplicateFacet,    ///< "duplicate": same facet listed twice
  TooLarge,          ///< "too-large": more items than the index type allows
  Coplanar,          ///< "coplanar": all points in one plane (no tetrahedron)
  Collinear,         ///< "collinear": all points on one line
  TooFewPoints,      ///< "too-few-points": fewer than 4 distinct points
  InvalidArgument,   ///< "invalid-argument": bad option or API argument
  Cancelled,         ///< "cancelled": the cancel flag was raised
  OutOfMemory,       ///< "out-of-memory": allocation failed
  Internal,          ///< "internal": a check inside the library failed (a bug)
  LimitReached,      ///< "limit": a phase hit its insertion bound (names the element)
  InvalidPlc,        ///< "invalid-plc": the PLC violates its definition (e.g. a vertex on a segment)
  SelfIntersection,  ///< "self-intersection": facets or segments intersect improperly (facet, other_facet)
  OpenBoundary,      ///< "open-boundary": the surface does not enclose a volume (facet, vertex = edge end)
};

/// Stable short name of an error code, e.g. "truncated".
const char* error_code_name(ErrorCode code);

/// What went wrong and where. Fields that do not apply are -1 / empty.
struct Error {
  ErrorCode code = ErrorCode::Ok;
  std::string message;   ///< human-readable, complete sentence without location
  std::string file;      ///< input file name, if any
  int64_t line = -1;     ///< 1-based text line
  int64_t record = -1;   ///< 0-based binary record (e.g. STL triangle)
  int64_t facet = -1;    ///< 0-based facet index in the Plc
  int64_t vertex = -1;   ///< 0-based vertex index
  int64_t other_facet = -1;  ///< second facet (duplicates, intersections)
  int64_t segment = -1;  ///< 0-based segment index in plc_segments() order

  /// "file:line: message (facet 3, vertex 7)" style one-line description.
  std::string to_string() const;
};

/// Result of an operation: ok() or an Error.
struct Status {
  Error error;
  bool ok() const { return error.code == ErrorCode::Ok; }
  static Status success() { return {}; }
};

// ---------------------------------------------------------------------------
// Piecewise linear complex
// ---------------------------------------------------------------------------

struct Vec3 {
  double x = 0, y = 0, z = 0;
};
inline bool operator==(const Vec3& a, const Vec3& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

/// A planar facet: one or more vertex loops in one plane (TetGen's polygons).
/// The region covered is the union of the loops' interiors minus the areas
/// marked by `holes` (points inside facet holes, as in TetGen .poly). A loop of
/// an STL/OFF triangle is the triangle itself. With `even_odd` the region is
/// instead the points enclosed by an odd number of loops (holes unused): the
/// form of a merged flat face (merge_flat_facets), whose loops are the cycles
/// of its boundary, the first an outer one.
struct Facet {
  std::vector<std::vector<VertexId>> loops;  ///< each loop has >= 3 vertices
  std::vector<Vec3> holes;                   ///< hole points lying in the facet's plane
  bool even_odd = false;                     ///< region by the even-odd rule (see above)
  int marker = 0;                            ///< boundary marker (TetGen)
  int64_t line = -1;    ///< source line of the facet (text formats), -1 if none
  int64_t record = -1;  ///< source record (binary formats), -1 if none
};

/// A region point: tets of the region containing `point` get `attribute`.
struct Region {
  Vec3 point;
  double attribute = 0;
  double max_volume = -1;  ///< -1: no constraint
};

/// A piecewise linear complex. Points are unique (identical coordinates are
/// welded exactly on input; nothing is welded by tolerance).
struct Plc {
  std::vector<Vec3> points;
  std::vector<Facet> facets;
  std::vector<std::array<VertexId, 2>> segments;  ///< explicit segments (not facet edges)
  std::vector<Vec3> holes;                        ///< volume hole points
  std::vector<Region> regions;
  /// Names the input gives facet markers, as (marker, name), sorted by
  /// marker: an OBJ file's groups ("g"/"o", markers 1, 2, ... in order of
  /// first use; faces before any group keep 0) and an ASCII STL's named
  /// solids (markers 0, 1, ... in order; an unnamed solid keeps 0). Written
  /// as Gmsh physical names.
  std::vector<std::pair<int, std::string>> marker_names;

  // Provenance, filled by the readers.
  std::string file;             ///< file name the PLC was read from
  size_t file_vertices = 0;     ///< vertex records in the file before welding
  size_t welded_vertices = 0;   ///< file records merged into an identical earlier point
};

/// Summary of a PLC, as printed by `cdt3d info`.
struct PlcInfo {
  size_t file_vertices = 0;   ///< vertex records in the file
  size_t points = 0;          ///< distinct points after exact welding
  size_t unreferenced = 0;    ///< points used by no facet or segment
  size_t facets = 0;
  size_t triangles = 0;       ///< triangles after fan-triangulating each loop
  size_t loops = 0;
  size_t segments = 0;        ///< explicit segments + distinct facet boundary edges
  size_t holes = 0;
  size_t regions = 0;
  Vec3 bbox_min, bbox_max;
};
PlcInfo plc_info(const Plc& plc);

/// Every segment of the PLC, sorted, each once: explicit segments and every
/// facet loop edge, as (lower id, higher id).
std::vector<std::array<VertexId, 2>> plc_segments(const Plc& plc);

// ---------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------

enum class FileFormat { Unknown, Stl, Off, Obj, Ply, Poly, Smesh, Node };

/// Format from a file name's extension (case-insensitive).
FileFormat format_from_name(const std::string& file_name);

/// Parse a PLC from bytes. `file_name` picks the format by extension and names
/// the file in errors. Runs check_plc() on success; on any error `out` is
/// left empty.
/// With check = false the PLC is handed back as parsed, without check_plc()
/// (for display of a model that fails its checks).
Status read_plc(const uint8_t* data, size_t size, const std::string& file_name, Plc& out,
                bool check = true);

/// Read a file from disk and parse it with read_plc() (check as there).
Status read_plc_file(const std::string& path, Plc& out, bool check = true);

/// Input checks: finite coordinates within kMaxCoordinate, indices in range,
/// facets with >= 3 distinct vertices and no repeated vertex in a loop, no
/// zero-area (collinear) loops, planar facets, no duplicate facets. Exact
/// predicates; no tolerances.
Status check_plc(const Plc& plc);

// ---------------------------------------------------------------------------
// Tetrahedral meshes and writers
// ---------------------------------------------------------------------------

/// A tetrahedral mesh as delivered to users: flat arrays.
struct TetMeshData {
  std::vector<double> points;      ///< 3 per point
  std::vector<uint32_t> tets;      ///< 4 per tet, positively oriented
  std::vector<uint32_t> faces;     ///< 3 per boundary/constrained face
  std::vector<int32_t> face_markers;    ///< per face: input facet marker (or id)
  std::vector<double> tet_attributes;   ///< per tet region attribute (may be empty)
  /// Names of facet markers from the input (Plc::marker_names).
  std::vector<std::pair<int, std::string>> marker_names;
};

/// TetGen .node/.ele/.face (0-based indices, with "# generated by cdt3d").
std::string write_node(const TetMeshData& m);
std::string write_ele(const TetMeshData& m);
std::string write_face(const TetMeshData& m);
/// Legacy VTK unstructured grid (ASCII), cell data: region attribute. Tets
/// are written right-handed (points 0, 2, 1, 3 of `tets`), as VTK's are.
std::string write_vtk(const TetMeshData& m);
/// Medit .mesh (MeshVersionFormatted 2), tets right-handed as in write_vtk.
std::string write_medit(const TetMeshData& m);
/// Gmsh MSH 4.1, ASCII or binary (binary bytes in the string, machine byte
/// order as the format allows). Nodes are numbered from 1 (point i is node
/// i + 1); tet t is element t + 1 (type 4) and face f element nt + f + 1
/// (type 2, the constrained faces). Volume physical groups: one per distinct
/// region attribute, named "region A"; its tag is A when every attribute is
/// a positive integer, else 1, 2, ... in increasing attribute order; without
/// attributes one group 1, "domain". Surface physical groups: one per
/// distinct facet marker, named "marker M" (or its name in
/// `m.marker_names`), tag M when M > 0, else the tags
/// after the largest positive marker in increasing marker order; without
/// markers one group 1, "boundary". Each group has one entity with the same
/// tag (volumes and surfaces, no points or curves); all nodes are listed on
/// the first volume entity. Tets are written with positive volume in Gmsh's
/// convention (two vertices swapped: write_msh and write_vtu list a tet as
/// points 0, 2, 1, 3 of `tets`).
std::string write_msh(const TetMeshData& m, bool binary);

// ---------------------------------------------------------------------------
// Constrained Delaunay tetrahedralization
// ---------------------------------------------------------------------------

/// Where a Steiner point lies and which step added it.
enum class SteinerKind : uint8_t {
  Segment = 1,  ///< on an input segment (segment recovery, boundary protection)
  Facet = 2,    ///< inside an input facet (boundary protection on a subface)
  Volume = 3,   ///< in the volume (break point of degeneracy removal)
};

/// Phase names reported to the progress callback, in order.
/// Read covers the input checks (check_plc and the self-intersection test);
/// Refine runs only with Options::quality.enabled.
enum class Phase { Read, Delaunay, Segments, Degeneracy, Facets, Carve, Refine, Done };
const char* phase_name(Phase phase);  ///< "read", "delaunay", "segments", ...
/// Inverse of phase_name; false for an unknown name.
bool phase_from_name(const std::string& name, Phase& out);

/// How step 3 (local degeneracies: five co-spherical vertices) is handled.
enum class DegeneracyMode : uint8_t {
  /// Default. Symbolic perturbation of the lifting (Simulation of Simplicity
  /// ordered by vertex id, the same in steps 1, 2 and 4): no vertex moves and
  /// no point is added; the perturbed point set is in general position, so
  /// with every segment a (perturbed) Delaunay edge a CDT exists (Shewchuk's
  /// CDT theorem) and step 4 recovers it.
  Symbolic = 0,
  /// Si & Gärtner §6 literally: perturb segment-safe vertices, else break
  /// points with boundary protection (reproduces the paper's point counts).
  /// Step 2 then splits segments by §5's rules 1-3 as published, not by the
  /// default projection splits (Statistics::split_projection).
  Paper = 1,
};

/// Quality refinement of the carved CDT (constrained Delaunay refinement,
/// Shewchuk 1998 and Si 2015): encroached subsegments and subfaces are split,
/// then the circumcentres of bad tets inserted, every point into the CDT with
/// its constrained faces respected, so the result is a CDT of the refined
/// PLC (validate() checks it). Input angles below 60 degrees between segments
/// and 90 degrees between facets are protected: tets whose badness comes
/// from such an angle are left as they are, so refinement terminates.
struct QualityOptions {
  bool enabled = false;       ///< run the Refine phase (CLI --quality, JS quality: {...})
  double radius_edge = 2.0;   ///< bound on circumradius / shortest edge, >= 1 (tetgen -q)
  double max_volume = -1;     ///< largest tet volume, -1: none (tetgen -a); Region::max_volume also applies
  /// Improvement pass after refinement (edge removal, 2-3 flips and moves
  /// of free vertices against slivers, like tetgen -O): raise the smallest
  /// dihedral angle towards this many degrees; 0 = no pass. At most 70.
  /// On by default, as tetgen -q optimises by default: refinement alone
  /// leaves slivers, whose radius-edge ratio can be small. The result is then
  /// a constrained tetrahedralization of the refined PLC but no longer a
  /// Delaunay one (Result::delaunay); 0 keeps it a CDT.
  double min_dihedral = 15;
  /// Stop refining after this many added points (0: 100 times the points
  /// of the CDT plus 1000000, plus 6 per smallest volume bound's worth of
  /// volume); reported in Statistics::refine_capped.
  size_t max_points = 0;
};

struct Options {
  DegeneracyMode degeneracy = DegeneracyMode::Symbolic;  ///< step 3 (see DegeneracyMode)
  bool keep_convex_hull = false;  ///< keep the tets outside the PLC (like tetgen -c)
  bool validate = false;          ///< run validate() on the result (and after each phase)
  int verbosity = 0;              ///< 0 quiet; 1 phase summary on stderr
  /// Reject self-intersecting input before meshing (exact; fast). Only turn it
  /// off for input known to be clean.
  bool check_intersections = true;
  /// Builds with threads (native, and the npm package's WebAssembly module
  /// for Node): run the self-intersection test on a second thread beside
  /// steps 1-2, which read the same PLC (below 20,000 points the input
  /// checks run there first, beside step 1; from 20,000 points step 1 first
  /// inserts its later rounds on two threads, and the test then starts
  /// after it), and half of the facet triangulations (large PLCs), of
  /// facet recovery's first pass and of the quality statistics (larger
  /// meshes) beside the other half (the result is the same either way; the
  /// browser module always uses one thread). tetrahedralize() may also be
  /// called from several threads at once.
  bool threads = true;
  /// Keep every input facet (triangle) as a facet of its own, like tetgen
  /// -pM. By default (false) flat faces are merged first, like TetGen's -p
  /// and the Diazzi-Attene CDT: facets joined by flat edges (two facets,
  /// exactly coplanar, on opposite sides, equal markers; see
  /// merge_flat_facets) form one facet, whose inner edges are no segments,
  /// which spares their Steiner points. Result faces then name the smallest
  /// input facet of their flat face (Result::flat_faces_merged), and
  /// validate() checks the result against the merged PLC.
  bool keep_triangles = false;
  QualityOptions quality;         ///< refinement after carving (off by default)
  Phase stop_after = Phase::Done; ///< stop after this phase (debugging); result holds that mesh
  /// Testing only: the first N times facet recovery runs, its first missing
  /// region counts as unrecoverable, which exercises the fallback that puts
  /// a Steiner point inside the facet (Statistics::facet_splits).
  size_t debug_forced_facet_splits = 0;
  /// Progress: called with the current phase and a fraction in [0, 1]. May be empty.
  void (*progress)(void* user, Phase phase, double fraction) = nullptr;
  void* progress_user = nullptr;
  /// Cancellation: checked regularly; when it becomes true the call returns
  /// ErrorCode::Cancelled.
  const volatile bool* cancel = nullptr;
};

/// A tet is numerically flat when |6V| / l_max^3 < kFlatTetRatio (V and the
/// longest edge l_max computed in doubles from the output coordinates).
inline constexpr double kFlatTetRatio = 1e-12;

struct Statistics {
  size_t input_points = 0, input_facets = 0, input_segments = 0;
  size_t points = 0, tets = 0, faces = 0;
  size_t steiner_segment = 0, steiner_facet = 0, steiner_volume = 0;
  size_t missing_segments = 0;     ///< input segments missing from the Delaunay tetrahedralization D0
  size_t rule1 = 0, rule2 = 0, rule3 = 0, acute_both = 0;  ///< segment recovery (§5)
  /// Segment recovery (step 2) by default: a missing subsegment is split at
  /// the projection of its reference point (as in §5: of the vertices in its
  /// diametral ball, the one with the largest circle through its ends), or
  /// at its midpoint when that projection falls in its outer fifths
  /// (split_projection); when the reference point lies on
  /// a segment sharing an endpoint e with this one, at the reference point's
  /// distance from e, so that the split points around e form a protecting
  /// ball (§5, Figure 4; split_shell). A segment split 64 times goes on by
  /// rules 1-3 (rule1...acute_both), whose termination §5 proves. Then split
  /// points that later splits made redundant are removed (split_removed; not
  /// in steiner_segment). DegeneracyMode::Paper uses rules 1-3 only.
  size_t split_projection = 0, split_shell = 0, split_removed = 0;
  size_t max_splits = 0;           ///< most points on one input segment
  size_t perturbations = 0, break_points = 0, protect_segment = 0, protect_facet = 0;  ///< §6
  /// Flat-face merging (Options::keep_triangles off): flat edges found, and
  /// facets of the merged PLC made of two or more input facets.
  size_t flat_edges = 0, merged_facets = 0;
  size_t missing_subfaces = 0, regions = 0, cavities = 0, largest_cavity = 0, fallbacks = 0;  ///< §7
  /// Steiner points inserted inside a facet because neither cavity
  /// retetrahedralization nor gift-wrapping recovered a missing region
  /// (counted in steiner_facet too).
  size_t facet_splits = 0;
  /// Numerically flat tets removed by flips before output.
  size_t flat_flips = 0;
  /// With the convex hull kept: numerically flat tets on the hull that no
  /// flip removed, given to the exterior (slivers of numerically no volume).
  size_t flat_peeled = 0;
  /// Points added by quality refinement, by where they lie (counted in
  /// steiner_segment / steiner_facet / steiner_volume too).
  size_t refine_segment = 0, refine_facet = 0, refine_volume = 0;
  /// Bad tets (radius-edge ratio above the bound, or volume above its
  /// limit) that refinement left, counted before the improvement pass: each
  /// fix it tried would have put a point too close to others (the floors
  /// that make refinement stop), encroached upon a constraint it could not
  /// split (with the improvement pass on, the sides of a facet corner below
  /// 10 degrees are not split), or made a numerically flat tet. They lie
  /// near small input angles and thin features (a thin plate, thin facets
  /// side by side); the final radius_edge_histogram counts what is left
  /// after the pass.
  size_t refine_skipped = 0;
  /// Of refine_skipped, the tets left on purpose at a facet corner of 10 to
  /// 60 degrees: their shortest edge joins the corner's two sides at about
  /// the same distance from it (Shewchuk's seditious edges), so a point that
  /// fixes one makes a shorter edge across the corner.
  size_t refine_small_angle = 0;
  size_t refine_capped = 0;   ///< 1 when QualityOptions::max_points stopped refinement
  /// Improvement pass (min_dihedral): flips (edge removals and 2-3 flips),
  /// vertex moves, and vertices added inside the volume (counted in
  /// steiner_volume too).
  size_t improve_flips = 0, improve_smooths = 0, improve_points = 0;
  /// Time per phase (ms). ms_delaunay is step 1, the one Delaunay
  /// tetrahedralization D0; ms_degeneracy is step 3, which with the symbolic
  /// perturbation is the search for its vertex order (before step 1, Delaunay
  /// tetrahedralizations of the co-spherical cells included). Natively
  /// ms_read includes the self-intersection test, which may run beside step
  /// 1 (Options::threads): the phases may then add up to more than ms_total.
  double ms_read = 0, ms_delaunay = 0, ms_segments = 0, ms_degeneracy = 0, ms_facets = 0,
         ms_carve = 0, ms_refine = 0, ms_total = 0;
  double min_dihedral = 0, max_dihedral = 0;  ///< degrees, over the output tets
  /// Output tets that are numerically flat: 6V computed in doubles from the
  /// output coordinates is below kFlatTetRatio * (longest edge)^3. Always 0
  /// on success (the pipeline removes them); reported for checks.
  size_t flat_tets = 0;
  std::array<size_t, 10> radius_edge_histogram{};  ///< ratio bins [1,1.5,2,3,5,10,20,50,100,inf)
  /// Per tet its smallest dihedral angle, in degree bins
  /// [0,1,5,10,15,20,30,40,50,60,inf).
  std::array<size_t, 10> dihedral_histogram{};
  /// The same three quality numbers for the CDT before refinement (equal to
  /// the final ones when quality refinement is off).
  double min_dihedral_before = 0;
  std::array<size_t, 10> radius_edge_histogram_before{};
  std::array<size_t, 10> dihedral_histogram_before{};
};

/// The CDT. Point i < input_points is PLC point i; the others are Steiner points.
struct Result {
  Status status;
  TetMeshData mesh;                   ///< faces = constrained faces (subfaces), face_markers = facet marker
  std::vector<uint32_t> face_facet;   ///< input facet index per face
  std::vector<uint32_t> edges;        ///< subsegments of the input segments, 2 point ids each
  std::vector<uint32_t> edge_segment; ///< per edge: input segment (plc_segments() order)
  size_t input_points = 0;
  std::vector<SteinerKind> steiner_kind;  ///< per Steiner point (index - input_points)
  std::vector<int64_t> steiner_parent;    ///< input segment (Segment) or facet (Facet) index, -1 (Volume)
  /// True for a constrained Delaunay tetrahedralization. False when the
  /// improvement pass (QualityOptions::min_dihedral) flipped tets or moved
  /// vertices: every facet and segment is still covered, but faces need not
  /// be locally Delaunay, and validate() does not check that.
  bool delaunay = true;
  /// True when flat faces were merged (Options::keep_triangles off): the
  /// mesh is a CDT of merge_flat_facets() of the input, face_facet names
  /// the smallest input facet of each flat face, and validate() merges too.
  bool flat_faces_merged = false;
  /// Per input facet, when flat faces were merged: the smallest input facet
  /// of its flat face (itself when it joined none), the id face_facet uses;
  /// the input facets of a face's flat face are those with the same entry.
  /// Empty with Options::keep_triangles and after map_to_input_facets().
  std::vector<uint32_t> flat_face_of;
  Statistics stats;
  /// Pairs of input facets that intersect improperly (filled when the status
  /// is SelfIntersection; all pairs found, for highlighting).
  std::vector<std::array<uint32_t, 2>> intersecting_facets;
};

/// Runs the four steps of Si & Gärtner (2005) and carves the exterior.
Result tetrahedralize(const Plc& plc, const Options& options = {});

/// The PLC with its flat faces merged (the default of tetrahedralize()): an
/// edge is flat when exactly two single-loop facets without holes and with
/// equal markers use it, it is no explicit segment, they are exactly
/// coplanar and lie on opposite sides of it. Facets joined by flat edges
/// become one even-odd facet (Facet::even_odd) whose loops are the cycles
/// of the group's boundary edges, the first an outer one oriented like the
/// group's smallest facet; all other facets are copied. An edge that is
/// inside two or more merged facets and on none of their loops (flat faces
/// crossing along it) is appended to out.segments. merged_into[f] is
/// the facet of `out` holding input facet f (facets of `out` in the order
/// of their smallest input facet). Returns the number of facets of `out`
/// made of two or more input facets; `flat_edges` (optional) gets the
/// number of flat edges. Exact; no point is constructed.
size_t merge_flat_facets(const Plc& plc, Plc& out, std::vector<uint32_t>& merged_into,
                         size_t* flat_edges = nullptr);

/// Step 1 alone: the Delaunay tetrahedralization of points xyz[3i..3i+2]
/// (duplicates inserted once). `tets` gets 4 point ids per tet, positively
/// oriented; `ms` (optional) the time taken.
Status delaunay_tetrahedralization(const std::vector<double>& xyz, std::vector<uint32_t>& tets,
                                   double* ms = nullptr);

/// The PLC's facets as triangles (each facet's constrained Delaunay
/// triangulation of its own vertices, loops and holes respected), for display:
/// 3 point ids per triangle in `triangles`, its facet in `triangle_facet`.
Status triangulate_surface(const Plc& plc, std::vector<uint32_t>& triangles,
                           std::vector<uint32_t>& triangle_facet);

// ---------------------------------------------------------------------------
// Repair
// ---------------------------------------------------------------------------

/// What repair() changed, step by step. All zero (and changed() false) when
/// the PLC was valid already: then the output is the input.
struct RepairReport {
  // Step 1: clean-up.
  size_t welded_points = 0;       ///< points merged into an identical earlier point
  size_t repeated_vertices = 0;   ///< repeated polygon vertices dropped (or cut at)
  size_t zero_area_polygons = 0;  ///< polygons of zero area (collinear or < 3 vertices) dropped
  size_t degenerate_facets = 0;   ///< facets dropped because no polygon with area was left
  size_t duplicate_facets = 0;    ///< facets dropped as repeats of an earlier facet
  // Step 1b, with RepairOptions::fill_holes.
  size_t filled_holes = 0;        ///< boundary loops closed
  size_t fill_triangles = 0;      ///< triangles added to close them
  size_t fill_points = 0;         ///< points added inside non-planar holes (constructed, rounded)
  size_t unfilled_holes = 0;      ///< loops left open (no triangulation without collinear triples)
  // Step 2.
  size_t nonplanar_facets = 0;    ///< non-planar facets split into triangles
  // Step 3: T-junctions.
  size_t tjunction_vertices = 0;  ///< (vertex, facet) incidences made explicit
  size_t tjunction_facets = 0;    ///< facets that gained such vertices
  // Step 4: crossings and overlaps.
  size_t crossing_pairs = 0;      ///< facet pairs found crossing or overlapping (first round)
  size_t crossing_facets = 0;     ///< facets re-triangulated along intersection segments
  size_t intersection_points = 0; ///< new points (constructed, rounded to doubles)
  size_t rounds = 0;              ///< rounds of step 4 (each re-checks exactly)
  size_t unresolved_pairs = 0;    ///< pairs (facets, explicit segments) still intersecting at the end
  /// Step 4 on explicit segments: the segments found crossing or touching
  /// a facet or another segment (first round), and the pieces repair split
  /// them into beyond one per segment (report.segment_source names the input
  /// segment of each piece).
  size_t crossing_segments = 0;
  size_t segment_splits = 0;
  // Step 5: the union of interpenetrating parts (after crossings were resolved).
  size_t inner_facets = 0;        ///< facets dropped as inside the union (or outside every part)
  /// 1 when crossings were resolved but the union was not formed (the
  /// facets, oriented like their input facets, do not close up: open
  /// pieces, inconsistent normals, coincident faces of two parts); every
  /// facet is then kept.
  size_t union_skipped = 0;
  /// Where the union was not formed: facets with the outside of the model on
  /// both sides (fins, sheets beside it) dropped; they bound no volume. Only
  /// when they are less than half of the surface's area, or with fill_holes.
  size_t outside_facets = 0;
  // Step 5 with RepairOptions::parts_as_regions (empty or 0 otherwise, and
  // when the union was not formed).
  size_t parts = 0;               ///< parts found: connected components of the input surface
  /// Per region attribute a (entry a - 1): the parts (0-based, numbered by
  /// their smallest input facet) that overlap there. Attribute p + 1 is
  /// where part p alone lies; overlaps of two or more parts get the
  /// attributes after the parts' (parts.size() + 1, ...), in lexicographic
  /// order of their part lists. An entry is empty when no cell has it (a
  /// part lying wholly inside another has no cell of its own).
  std::vector<std::vector<uint32_t>> region_parts;
  /// Per output facet: its axis k (the largest component of its normal)
  /// and the region attribute on its +k side and on its -k side (0: outside
  /// the union, -1: not known). map_to_input_facets() reads them to give
  /// every tet of the mesh its region.
  std::vector<uint8_t> facet_axis;
  std::vector<std::array<int32_t, 2>> facet_regions;
  size_t input_points = 0, input_facets = 0, points = 0, facets = 0;
  double ms = 0;
  /// Per output facet: the input facet it comes from (provenance).
  std::vector<uint32_t> facet_source;
  /// Per output explicit segment: the input segment it is a piece of.
  std::vector<uint32_t> segment_source;
  /// Input facets that some step changed (sorted), for highlighting.
  std::vector<uint32_t> changed_facets;
  bool changed() const;
};

/// Repairs a PLC exactly, in this order: (1) identical points welded,
/// repeated polygon vertices, zero-area polygons and duplicate facets
/// dropped; (2) non-planar facets split into triangles; (3) T-junctions: a
/// vertex lying on another facet's edge or inside it becomes a vertex of
/// that facet (no new coordinates); (4) crossing facets get their
/// intersection segments as edges (new points rounded to doubles, checked
/// again exactly, a bounded number of rounds); (5) where (4) resolved
/// crossings, the facets inside the union of the parts are dropped
/// (RepairOptions::union_of_parts; with RepairOptions::parts_as_regions
/// only those between cells of the same parts). Every output facet keeps the
/// marker and source line/record of its input facet (report.facet_source).
/// `plc` may fail check_plc() (read it with read_plc(..., check = false)).
/// Errors: what repair cannot fix (non-finite coordinates, indices out of
/// range, facets still intersecting: SelfIntersection naming input facets);
/// `out` then holds the PLC as far as it got. An open surface is left open
/// unless `options.fill_holes`.
struct RepairOptions {
  /// After step 3 (T-junctions), close every boundary loop (edges of one facet only) with
  /// triangles of its own vertices, of least total area (CLI --fill-holes,
  /// JS repair: { fillHoles: true }); a non-planar loop's patch is then
  /// refined with new points to the size of the triangles around the hole
  /// and smoothed (Liepa 2003; RepairReport::fill_points); the patch takes the marker and
  /// provenance of the facet along the loop and goes through steps 3-4.
  /// Asks for a closed solid: where crossings were resolved but the union
  /// was not formed, every facet with the outside on both sides goes
  /// (RepairReport::outside_facets), not only fins that are the lesser part.
  bool fill_holes = false;
  /// After crossings were resolved, the domain is the union of the parts
  /// (the default): the cells of winding number at least 1 of the input
  /// surfaces, oriented by their facets' vertex order (right-hand rule,
  /// normals outwards; a part with inward normals is a hole in the others,
  /// and a model whose normals all point inwards counts as turned inside
  /// out). Facets with the union on both sides, or on neither, are dropped.
  /// Where the facets, oriented like their input facets, do not close up
  /// (open pieces, inconsistent normals, coincident faces of two parts),
  /// every facet is kept (RepairReport::union_skipped). False (CLI
  /// --keep-inner, JS repair: { union: false }): every cell of the
  /// arrangement is meshed, bounded by internal facets.
  bool union_of_parts = true;
  /// Every part a region of its own (CLI --parts-as-regions, JS repair: {
  /// partsAsRegions: true }): the domain is still the union, but facets
  /// between cells that lie in different sets of parts stay as internal
  /// facets, and after tetrahedralize() map_to_input_facets() gives every
  /// tet the region attribute of its set of parts (RepairReport::
  /// region_parts: part p alone is attribute p + 1, each overlap of parts a
  /// region of its own after those). A part is a connected component of the
  /// input surface, facets joined across shared edges once identical points
  /// are welded (OBJ groups and STL solids do not matter: one CAD body is
  /// often exported as many groups). Runs even where no parts cross (nested
  /// or disjoint parts are labelled too). Input region points are dropped;
  /// volume holes stay. Needs union_of_parts (InvalidArgument otherwise).
  /// Where the union is not formed (RepairReport::union_skipped), the mesh
  /// keeps the attributes tetrahedralize() gives its regions.
  bool parts_as_regions = false;
  /// Testing only: the winding numbers of the union from a tetrahedralization
  /// of the arrangement instead of exact ray casting (the fallback where no
  /// ray of a patch is clear of edges and vertices).
  bool debug_union_by_mesh = false;
};
Status repair(const Plc& plc, Plc& out, RepairReport& report, const RepairOptions& options = {});

/// After tetrahedralize() of a repaired PLC: makes the result name input
/// facets (face_facet, Steiner parents of facet points, error facets and
/// intersecting pairs) through report.facet_source. Validate before this.
/// Segment numbers (edge_segment, parents of segment points) stay those of
/// the repaired PLC: its edges are not all input edges. With
/// RepairOptions::parts_as_regions it also sets result.mesh.tet_attributes
/// to the regions of report.region_parts (0 for tets outside the union,
/// which only Options::keep_convex_hull keeps): each connected set of tets
/// takes the region on its side of a constrained face it touches, found by
/// exact orientation tests.
void map_to_input_facets(const RepairReport& report, Result& result);

/// The PLC as a TetGen .poly file (numbered from 0, coordinates with %.17g,
/// which reads back exactly): points, facets with their polygons, facet holes
/// and markers, explicit segments as 2-vertex polygons, volume holes, regions.
std::string write_poly(const Plc& plc);

/// VTK XML unstructured grid (.vtu) of the tets, every array raw binary in
/// one appended block (UInt64 headers, machine byte order, named in the
/// file). Cell data: "region" (Float64 region attribute, only when the
/// result has attributes) and "min_dihedral" (Float64, the tet's smallest
/// dihedral angle in degrees); point data: "steiner_kind" (UInt8: 0 input
/// point, else SteinerKind). Points Float64, connectivity and offsets Int64.
std::string write_vtu(const Result& r);

/// Checks a result against its PLC with exact predicates: valid
/// tetrahedralization (positive tets, face-adjacency consistent, no gaps
/// inside the domain), every input facet exactly covered by constrained
/// faces, every segment a chain of edges, constrained Delaunay property
/// (every interior face that is not constrained is locally Delaunay), the
/// last only when result.delaunay (see Result::delaunay).
Status validate(const Plc& plc, const Result& result);

}  // namespace cdt3d
