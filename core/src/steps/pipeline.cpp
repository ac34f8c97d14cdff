// tetrahedralize(): the four steps of Si & Gärtner (2005) in order, then
// carving, packaged as the public Result.
//
//   1. Delaunay tetrahedralization D0 of the PLC points (§4 (1), delaunay.cpp)
//   2. segment recovery D0 -> D1 (§5, segment_recovery.cpp)
//   3. local degeneracy removal D1 -> D2 (§6, degeneracy.cpp)
//   4. facet recovery D2 -> CDT (§7, facet_triangulate.cpp + facet_recovery.cpp)
//   5. exterior and hole removal, region attributes (carve.cpp)
//   6. optional quality refinement of the carved CDT (refine.cpp)
//
// Each phase returns a Status naming the element it failed on; this file only
// sequences them, times them, reports progress, and converts the mesh.
#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "beside.hpp"
#include "carve.hpp"
#include "degeneracy.hpp"
#include "delaunay.hpp"
#include "facet_merge.hpp"
#include "facet_recovery.hpp"
#include "flat_flips.hpp"
#include "geometry.hpp"
#include "plc_check.hpp"
#include "plc_intersect.hpp"
#include "refine.hpp"
#include "segment_recovery.hpp"
#include "sos_order.hpp"
#include "stats.hpp"
#include "status.hpp"
#include "subfaces.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

const char* phase_name(Phase phase) {
  switch (phase) {
    case Phase::Read: return "read";
    case Phase::Delaunay: return "delaunay";
    case Phase::Segments: return "segments";
    case Phase::Degeneracy: return "degeneracy";
    case Phase::Facets: return "facets";
    case Phase::Carve: return "carve";
    case Phase::Refine: return "refine";
    case Phase::Done: return "done";
  }
  return "done";
}

bool phase_from_name(const std::string& name, Phase& out) {
  for (Phase p : {Phase::Read, Phase::Delaunay, Phase::Segments, Phase::Degeneracy, Phase::Facets,
                  Phase::Carve, Phase::Refine, Phase::Done}) {
    if (name == phase_name(p)) {
      out = p;
      return true;
    }
  }
  return false;
}

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Share of the total run time a phase usually takes (measured on the corpus);
// only used to turn per-phase progress into one overall fraction. With
// quality refinement the phases before it share the first third.
constexpr double kPhaseStart[] = {0.0, 0.02, 0.45, 0.6, 0.7, 0.95, 1.0, 1.0};
constexpr double kRefineStart = 0.33;

// Facet Steiner points (one per failed region) before giving up: each run
// of steps 1-4 costs a full meshing, and a valid PLC needs few.
constexpr size_t kMaxFacetSplits = 64;

// The perturbation order search (sos_order.hpp): orders tried at most, and
// only for PLCs up to this many points (the input order and the chosen one
// each cost a full step 1, the others a retriangulation of the co-spherical
// cells).
constexpr size_t kSosOrderRounds = 8;
constexpr size_t kMaxSosOrderPoints = 200000;
// Below this many facets the self-intersection test takes about what
// starting a thread costs, so it runs here; from this many on, the second
// thread pays.
constexpr size_t kMinFacetsBeside = 1000;

// The exact self-intersection test, on a second thread where there is one.
// It only reads the PLC, so it runs beside the pipeline: from the end of
// step 1 (which has both cores to itself, DelaunayOptions::threads) through
// step 2, which it stops when it finds a pair; the pipeline waits for the
// verdict before step 4, whose work on an intersecting PLC would be wasted
// or fail far from the cause, and lets an intersection override any error
// of the steps before. The thread's own clock gives ms(), the time the test
// took (msRead counts it, so the phases may add up to more than msTotal).
// With `checks` the thread first runs check_plc, lists plc_segments and
// makes their init_segments, beside step 1 on the points (which passed
// check_plc_points): checked() waits for that, and the test follows only
// when the checks passed.
class IntersectionTest {
 public:
  IntersectionTest() = default;
  IntersectionTest(const IntersectionTest&) = delete;
  IntersectionTest& operator=(const IntersectionTest&) = delete;
  ~IntersectionTest() { join(); }

  // Runs the test, on a thread if `beside` and threads exist (and one can be
  // started), else right here. *found_any (if given) becomes true when the
  // test ends with a pair found.
  void start(const Plc& plc, bool beside, std::atomic<bool>* found_any = nullptr,
             bool checks = false) {
    found_any_ = found_any;
    checks_ = checks;
#ifdef CDT3D_HAS_THREADS
    // Else (no thread to be had) the test runs here.
    if (beside && threads_available() && thread_.start([this, &plc] { run(plc); })) return;
#else
    (void)beside;
#endif
    run(plc);
  }
  // With `checks`: waits for them and returns check_plc's status; the first
  // call on success moves plc_segments into *segments (if given). An
  // allocation failure on the thread is rethrown here.
  Status checked(std::vector<std::array<VertexId, 2>>* segments = nullptr) {
#ifdef CDT3D_HAS_THREADS
    {
      std::unique_lock<std::mutex> lock(mutex_);
      published_cv_.wait(lock, [this] { return published_; });
    }
#endif
    if (checks_threw_) found();  // joins and rethrows
    if (segments && checks_status_.ok()) *segments = std::move(segments_);
    return checks_status_;
  }
  // After checked() passed: init_segments of the PLC, made beside step 1.
  SegmentSet take_segment_set() { return std::move(segment_set_); }
  // The pairs found (after the thread finished); an allocation failure on
  // the thread is rethrown here, for tetrahedralize()'s handler.
  const std::vector<Intersection>& found() {
    join();
    if (failure_) std::rethrow_exception(failure_);
    return found_;
  }
  double ms() const { return ms_; }
  /// Whether the test has ended (found() then does not wait).
  bool finished() const { return finished_.load(std::memory_order_acquire); }

 private:
  void run(const Plc& plc) {
    const auto t0 = Clock::now();
#ifdef CDT3D_HAS_THREADS
    try {
      if (run_checks(plc)) find_self_intersections(plc, found_);
    } catch (...) {
      failure_ = std::current_exception();
      checks_threw_ = !checks_done_;
    }
    publish();  // also after a failure: checked() must not wait forever
#else
    if (run_checks(plc)) find_self_intersections(plc, found_);
#endif
    ms_ = ms_since(t0);
    if (found_any_ && (!found_.empty() || failure_)) found_any_->store(true);
    finished_.store(true, std::memory_order_release);
  }
  // check_plc, plc_segments and init_segments when asked for; false when
  // the checks failed.
  bool run_checks(const Plc& plc) {
    if (!checks_) return true;
    checks_status_ = check_plc(plc);
    if (checks_status_.ok()) {
      segments_ = plc_segments(plc);
      init_segments(plc, segment_set_, std::vector<std::array<VertexId, 2>>(segments_));
    }
    checks_done_ = true;
    publish();
    return checks_status_.ok();
  }
  void publish() {
#ifdef CDT3D_HAS_THREADS
    std::lock_guard<std::mutex> lock(mutex_);
    published_ = true;
    published_cv_.notify_all();
#endif
  }
  void join() {
#ifdef CDT3D_HAS_THREADS
    thread_.join();
#endif
  }

  std::vector<Intersection> found_;
  std::exception_ptr failure_;
  std::atomic<bool>* found_any_ = nullptr;
  std::atomic<bool> finished_{false};
  double ms_ = 0;
  bool checks_ = false;
  // Written before the checks are published, read by checked() after.
  bool checks_done_ = false, checks_threw_ = false;
  Status checks_status_;
  std::vector<std::array<VertexId, 2>> segments_;
  SegmentSet segment_set_;
#ifdef CDT3D_HAS_THREADS
  BesideThread thread_;
  std::mutex mutex_;
  std::condition_variable published_cv_;
  bool published_ = false;
#endif
};

// Every point of `plc` is a vertex of some facet loop.
bool all_points_on_loops(const Plc& plc) {
  std::vector<uint8_t> used(plc.points.size(), 0);
  size_t count = 0;
  for (const Facet& f : plc.facets)
    for (const auto& loop : f.loops)
      for (VertexId v : loop)
        if (v < used.size() && !used[v]) used[v] = 1, ++count;
  return count == plc.points.size();
}

class Pipeline {
 public:
  Pipeline(const Plc& plc, const Options& options, Result& out)
      : input_(plc), plc_(&plc), opt_(options), out_(out) {}

  void run();
  void finish(const Plc& input);

 private:
  bool cancelled() const { return opt_.cancel != nullptr && *opt_.cancel; }
  bool refining() const { return opt_.quality.enabled && opt_.stop_after >= Phase::Refine; }
  static void refine_progress(void* self, double fraction) {
    static_cast<Pipeline*>(self)->progress(Phase::Refine, fraction);
  }
  void progress(Phase phase, double fraction) {
    if (!opt_.progress) return;
    const int i = static_cast<int>(phase);
    double f = phase == Phase::Done
                   ? 1.0
                   : kPhaseStart[i] + (kPhaseStart[i + 1] - kPhaseStart[i]) * fraction;
    if (refining() && phase != Phase::Done)
      f = phase == Phase::Refine ? kRefineStart + (1 - kRefineStart) * fraction : kRefineStart * f;
    opt_.progress(opt_.progress_user, phase, std::min(1.0, std::max(0.0, f)));
  }
  // Starts `phase`; false when the run was cancelled.
  bool begin(Phase phase);
  bool end(Phase phase, const Status& st, double* ms);
  bool fail(const Status& st) {
    out_.status = st;
    return false;
  }
  void report_input_ids(const Plc& input);
  void mesh_to_result(const std::vector<TetId>& tets, const std::vector<double>* attributes,
                      const CarveResult* carved);
  Status check_open_facets(const CarveResult& carved) const;
  bool mesh_steps(FacetRecoveryStats& fst);
  void add_facet_split(const FacetRecoveryStats& fst);
  Status insert_facet_splits();
  Status intersection_verdict(IntersectionTest& test, bool beside);
  bool read_phase(IntersectionTest& intersections);
  bool merge_flat_faces();
  void schedule_test(bool merging);
  void choose_order(IntersectionTest& intersections);
  bool after_order(IntersectionTest& intersections);
  bool await_intersections();
  bool take_ended_test();
  void release_work();
  // Step 1's options: two threads where the run may use them.
  DelaunayOptions delaunay_options() const {
    DelaunayOptions o;
    o.threads = opt_.threads;
    return o;
  }

  struct FacetSplit {
    uint32_t facet;
    double xyz[3];
  };
  std::vector<FacetSplit> facet_splits_;  ///< Steiner points added inside facets, in order

  const Plc& input_;            // what the self-intersection test reads
  const Plc* plc_;              // the input, or merged_ when facets were merged
  Plc merged_;                  // merge_flat_facets of the input (when it joined some)
  FlatFaceInsides insides_;     // what lies inside merged_'s facets (point ids of plc_)
  std::vector<uint32_t> rep_;   // per facet of merged_: its smallest input facet
  Plc permuted_;                // *plc_ with its points in order_ (sos_order.hpp)
  std::vector<VertexId> order_; // point k of permuted_ is input point order_[k]; empty: none
  double ms_order_ = 0;         // time spent choosing order_ (step 3), D0 not included
  double ms_d0_ = 0;            // time spent building d0_ (step 1)
  TetMesh d0_;                  // step 1's mesh, computed while choosing order_
  const Options& opt_;
  Result& out_;
  Clock::time_point t_phase_;

  TetMesh mesh_;
  SegmentSet segs_;
  std::vector<std::vector<VertexId>> facet_interior_;
  std::vector<VertexId> volume_points_;
  Subfaces subfaces_;
  std::vector<HalfFace> subface_hf_;  // per subface: a half-face (recover_facets)
  // The PLC passed the self-intersection test, has no explicit segments and
  // no point outside the facets' loops, so no point or segment lies inside
  // a facet (triangulate_facets' `nothing_embedded`).
  bool nothing_embedded_ = false;
  // plc_segments(*plc_) from the perturbation-order search, for step 2 (empty
  // when not computed or used up).
  std::vector<std::array<VertexId, 2>> input_segments_;
  // init_segments of *plc_ made beside step 1 (empty when not made or used).
  SegmentSet initial_segments_;
  // The self-intersection test while it runs beside steps 1-2, and the flag
  // it raises for step 2 when it found a pair.
  IntersectionTest* pending_test_ = nullptr;
  std::atomic<bool> intersecting_{false};
  // Where the test and the checks run (schedule_test).
  bool test_beside_ = false, test_after_d0_ = false, checks_beside_ = false;
  bool done_ = false;  // run() got to the end
  bool error_in_input_ids_ = false;  // the run's error came from the test (input_)
};

bool Pipeline::begin(Phase phase) {
  if (cancelled()) {
    out_.status.error.code = ErrorCode::Cancelled;
    out_.status.error.message = std::string("Cancelled before the ") + phase_name(phase) + " phase.";
    return false;
  }
  progress(phase, 0);
  t_phase_ = Clock::now();
  return true;
}

bool Pipeline::end(Phase phase, const Status& st, double* ms) {
  *ms = ms_since(t_phase_);
  if (!st.ok()) return fail(st);
  if (opt_.validate && phase < Phase::Carve && phase != Phase::Read) {
    // Cheap invariants after each phase: adjacency, orientation, ghosts.
    Status mc = check_mesh(mesh_);
    if (!mc.ok()) {
      mc.error.message = std::string("After the ") + phase_name(phase) +
                         " phase the mesh is invalid: " + mc.error.message;
      return fail(mc);
    }
  }
  progress(phase, 1);
  return true;
}

// Every facet of a closed domain bounds a kept tet on at least one side. A
// facet with none lies outside what was kept: the surface around it is open
// (the exterior leaked in through a gap) or it floats outside the domain.
Status Pipeline::check_open_facets(const CarveResult& carved) const {
  std::vector<uint8_t> bounded(plc_->facets.size(), 0);
  for (uint32_t f : carved.face_facet)
    if (f < bounded.size()) bounded[f] = 1;
  for (uint32_t f = 0; f < plc_->facets.size(); ++f) {
    if (bounded[f]) continue;
    return make_error(ErrorCode::OpenBoundary,
                      "The surface does not enclose a volume around facet " + std::to_string(f) +
                          ": no kept tetrahedron touches it (the surface is open or the facet "
                          "lies outside the domain). Use keep-hull to mesh open surfaces as "
                          "constraints inside the convex hull.")
        .facet_of(*plc_, f);
  }
  return Status::success();
}

// The phases number points, facets and segments of the PLC they mesh: after
// merge_flat_facets, the merged PLC; after segment_friendly_order, its
// points renumbered. The Result names those of the input: a point by its
// input index, a merged facet by its smallest input facet, a segment by its
// index in the input's segments.
void Pipeline::report_input_ids(const Plc& input) {
  if (rep_.empty() && order_.empty()) return;
  const size_t nin = input.points.size();
  auto vertex = [&](int64_t v) -> int64_t {
    return order_.empty() || v < 0 || v >= static_cast<int64_t>(nin) ? v : order_[v];
  };
  auto facet = [&](int64_t f) { return f >= 0 && f < static_cast<int64_t>(rep_.size()) ? rep_[f] : f; };
  const auto mine = plc_segments(*plc_), theirs = plc_segments(input);
  auto segment = [&](int64_t s) -> int64_t {
    if (s < 0 || s >= static_cast<int64_t>(mine.size())) return s;
    std::array<VertexId, 2> e = {static_cast<VertexId>(vertex(mine[s][0])),
                                 static_cast<VertexId>(vertex(mine[s][1]))};
    if (e[0] > e[1]) std::swap(e[0], e[1]);
    auto it = std::lower_bound(theirs.begin(), theirs.end(), e);
    return it != theirs.end() && *it == e ? it - theirs.begin() : -1;
  };
  TetMeshData& m = out_.mesh;
  if (!order_.empty() && m.points.size() >= 3 * nin) {
    const std::vector<double> mine_xyz(m.points.begin(), m.points.begin() + 3 * nin);
    for (size_t k = 0; k < nin; ++k)
      std::copy(&mine_xyz[3 * k], &mine_xyz[3 * k] + 3, &m.points[3 * static_cast<size_t>(order_[k])]);
    for (auto* ids : {&m.tets, &m.faces, &out_.edges})
      for (uint32_t& v : *ids) v = static_cast<uint32_t>(vertex(v));
  }
  for (uint32_t& f : out_.face_facet) f = static_cast<uint32_t>(facet(f));
  for (uint32_t& e : out_.edge_segment) e = static_cast<uint32_t>(segment(e));
  for (size_t i = 0; i < out_.steiner_kind.size(); ++i) {
    int64_t& p = out_.steiner_parent[i];
    if (out_.steiner_kind[i] == SteinerKind::Facet) p = facet(p);
    if (out_.steiner_kind[i] == SteinerKind::Segment) p = segment(p);
  }
  if (error_in_input_ids_) return;  // the self-intersection test read the input
  Error& e = out_.status.error;
  e.facet = facet(e.facet);
  e.other_facet = facet(e.other_facet);
  e.segment = segment(e.segment);
  e.vertex = vertex(e.vertex);
}

// Copies the kept tets into the public Result, dropping Steiner points that
// no kept tet uses (e.g. break points outside the domain, §6) and
// renumbering the rest after the input points.
void Pipeline::mesh_to_result(const std::vector<TetId>& tets,
                              const std::vector<double>* attributes, const CarveResult* carved) {
  const size_t nin = plc_->points.size();
  const size_t nv = mesh_.num_vertices();
  std::vector<uint32_t> newid(nv, kNone);
  for (size_t v = 0; v < nin; ++v) newid[v] = static_cast<uint32_t>(v);
  std::vector<uint8_t> used(nv, 0);
  for (TetId t : tets)
    for (int k = 0; k < 4; ++k) used[mesh_.vertex(t, k)] = 1;
  if (carved)
    for (const auto& f : carved->faces)
      for (VertexId v : f) used[v] = 1;

  // Kind and parent of every Steiner vertex, from the phases' records.
  std::vector<SteinerKind> kind(nv, SteinerKind::Volume);
  std::vector<int64_t> parent(nv, -1);
  for (const SegmentVertex& sv : segs_.steiner) {
    kind[sv.vertex] = SteinerKind::Segment;
    parent[sv.vertex] = sv.segment;
  }
  for (uint32_t f = 0; f < facet_interior_.size(); ++f)
    for (VertexId v : facet_interior_[f])
      if (v >= nin && v < nv) kind[v] = SteinerKind::Facet, parent[v] = f;

  TetMeshData& m = out_.mesh;
  m.points.assign(mesh_.coords.begin(), mesh_.coords.begin() + 3 * nin);
  for (size_t v = nin; v < nv; ++v) {
    if (!used[v]) continue;
    newid[v] = static_cast<uint32_t>(m.points.size() / 3);
    m.points.insert(m.points.end(), mesh_.coords.begin() + 3 * v, mesh_.coords.begin() + 3 * v + 3);
    out_.steiner_kind.push_back(kind[v]);
    out_.steiner_parent.push_back(parent[v]);
  }
  m.tets.reserve(4 * tets.size());
  for (TetId t : tets)
    for (int k = 0; k < 4; ++k) m.tets.push_back(newid[mesh_.vertex(t, k)]);
  if (attributes) m.tet_attributes = *attributes;
  if (carved) {
    for (size_t i = 0; i < carved->faces.size(); ++i) {
      for (int k = 0; k < 3; ++k) m.faces.push_back(newid[carved->faces[i][k]]);
      const uint32_t f = carved->face_facet[i];
      out_.face_facet.push_back(f);
      m.face_markers.push_back(f < plc_->facets.size() ? plc_->facets[f].marker : 0);
    }
  }
  // Subsegments whose two ends are kept (the others lie outside the domain).
  std::vector<std::array<uint32_t, 3>> sub;
  segs_.subsegments(sub);
  for (const auto& e : sub) {
    if (newid[e[0]] == kNone || newid[e[1]] == kNone) continue;
    out_.edges.push_back(newid[e[0]]);
    out_.edges.push_back(newid[e[1]]);
    out_.edge_segment.push_back(e[2]);
  }
  out_.input_points = nin;
  size_statistics(out_);
}

// Steps 1-4 on a fresh mesh. False on failure (out_.status says why; fst
// names the subface facet recovery could not recover, if any).
bool Pipeline::mesh_steps(FacetRecoveryStats& fst) {
  Statistics& s = out_.stats;
  Status st;
  mesh_ = TetMesh();
  segs_ = SegmentSet();
  subfaces_ = Subfaces();
  volume_points_.clear();
  // Step 1, then the facet Steiner points of earlier attempts.
  if (!begin(Phase::Delaunay)) return false;
  DelaunayStats dstats;
  if (d0_.live_tets > 0 && facet_splits_.empty()) {
    mesh_ = std::move(d0_);  // computed while choosing the order
    d0_ = TetMesh();
  } else {
    st = delaunay_tetrahedralize(mesh_, &plc_->points[0].x, plc_->points.size(), nullptr, &dstats,
                                 delaunay_options());
  }
  if (!initial_segments_.input.empty()) {
    segs_ = std::move(initial_segments_);  // made beside step 1
    initial_segments_ = SegmentSet();
    input_segments_.clear();
  } else if (!input_segments_.empty()) {
    init_segments(*plc_, segs_, std::move(input_segments_));
    input_segments_.clear();
  } else {
    init_segments(*plc_, segs_);
  }
  s.input_segments = segs_.input.size();
  facet_interior_.assign(plc_->facets.size(), {});
  for (size_t f = 0; f < insides_.vertices.size() && f < facet_interior_.size(); ++f)
    facet_interior_[f] = insides_.vertices[f];  // input vertices inside flat faces
  if (st.ok()) st = insert_facet_splits();
  if (!end(Phase::Delaunay, st, &s.ms_delaunay)) return false;
  s.ms_delaunay += ms_d0_;
  s.ms_degeneracy = ms_order_;

  // Step 2.
  if (opt_.stop_after >= Phase::Segments) {
    if (!begin(Phase::Segments)) return false;
    SegmentRecoveryStats sst;
    const SplitMode mode =
        opt_.degeneracy == DegeneracyMode::Paper ? SplitMode::Rules : SplitMode::Projection;
    st = recover_segments(mesh_, segs_, &sst, opt_.cancel, mode, &intersecting_);
    s.missing_segments = sst.missing_initially;
    s.rule1 = sst.rule1, s.rule2 = sst.rule2, s.rule3 = sst.rule3, s.acute_both = sst.acute_both;
    s.split_projection = sst.projection, s.split_shell = sst.shell, s.split_removed = sst.removed;
    s.max_splits = sst.max_splits;
    if (!end(Phase::Segments, st, &s.ms_segments)) return false;
  }

  // Step 3. Symbolically (default) there is nothing left to do here: the
  // perturbation's order was chosen before step 1 (its time is already in
  // msDegeneracy), and the predicates of steps 1, 2 and 4 share that one
  // perturbation, so D1 has no local degeneracy.
  if (opt_.stop_after >= Phase::Degeneracy && opt_.degeneracy == DegeneracyMode::Paper) {
    if (!begin(Phase::Degeneracy)) return false;
    DegeneracyStats gst;
    st = remove_local_degeneracies(*plc_, mesh_, segs_, facet_interior_, volume_points_, &gst,
                                   opt_.cancel);
    s.perturbations = gst.perturbations, s.break_points = gst.break_points;
    s.protect_segment = gst.protect_segment, s.protect_facet = gst.protect_facet;
    double ms = 0;
    if (!end(Phase::Degeneracy, st, &ms)) return false;
    s.ms_degeneracy += ms;
  }

  // Segments are split by recover_segments only in steps 2 and 3.
  segs_.release_planes();

  // Step 4. On a large PLC the self-intersection test may still run beside:
  // step 4 does not wait for it, its verdict comes when it has ended, at the
  // latest after step 4 (run()). An intersecting PLC makes step 4's work
  // wasted and its outcome moot (the intersection is the run's error,
  // whatever step 4 did), so step 4 stops when the test finds a pair. Until
  // the test's thread is joined step 4 keeps to this thread: halves beside
  // would share the test's core, and the WebAssembly module's one pool
  // worker is the test's (BesideThread would refuse a second thread).
  if (opt_.stop_after >= Phase::Facets) {
    if (!begin(Phase::Facets)) return false;
    if (!take_ended_test()) return false;
    st = triangulate_facets(*plc_, segs_, mesh_, facet_interior_, subfaces_, nothing_embedded_,
                            opt_.threads && !pending_test_);
    const bool force = facet_splits_.size() < opt_.debug_forced_facet_splits;
    if (st.ok() && !take_ended_test()) return false;
    if (st.ok())
      st = recover_facets(mesh_, subfaces_, &fst, opt_.cancel, force, &subface_hf_,
                          opt_.threads && !pending_test_, &intersecting_);
    s.missing_subfaces = fst.missing_initially, s.regions = fst.regions;
    s.cavities = fst.cavities, s.largest_cavity = fst.largest_cavity, s.fallbacks = fst.fallbacks;
    if (!end(Phase::Facets, st, &s.ms_facets)) return false;
  }

  return true;
}

// A Steiner point at the centroid of the subface facet recovery could not
// recover, for its facet. Rounded to doubles, like every constructed point
// (§5): the facet is then only nearly planar near it, which the later steps
// already handle for rounded segment points (flat-tet test, validator).
void Pipeline::add_facet_split(const FacetRecoveryStats& fst) {
  double c[3] = {0, 0, 0};
  for (VertexId v : fst.unrecovered)
    for (int k = 0; k < 3; ++k) c[k] += mesh_.point(v)[k] / 3;
  facet_splits_.push_back({fst.unrecovered_facet, {c[0], c[1], c[2]}});
}

// Inserts the facet Steiner points of earlier attempts into D0.
Status Pipeline::insert_facet_splits() {
  if (facet_splits_.empty()) return Status::success();
  PointInserter ins(mesh_);
  for (const FacetSplit& fs : facet_splits_) {
    InsertResult res;
    Status st = ins.insert_point(fs.xyz, ins.last_tet(), kVertexSteiner, &res);
    if (!st.ok()) return st;
    if (!res.duplicate) facet_interior_[fs.facet].push_back(res.vertex);
  }
  return Status::success();
}

// The self-intersection test's pairs into the Result, and its error. Beside
// the steps, its time joins msRead (the Read phase had ended without it).
Status Pipeline::intersection_verdict(IntersectionTest& test, bool beside) {
  const std::vector<Intersection>& found = test.found();
  if (beside) out_.stats.ms_read += test.ms();
  for (const Intersection& x : found) out_.intersecting_facets.push_back({x.a, x.b});
  const Status st = self_intersection_error(input_, found);
  if (!st.ok()) error_in_input_ids_ = true;
  return st;
}

// Waits for the test running beside the steps, if one is; false (with its
// error as the run's, replacing any error of the steps, which an
// intersection explains) when it found a pair.
bool Pipeline::await_intersections() {
  if (!pending_test_) return true;
  IntersectionTest& test = *pending_test_;
  pending_test_ = nullptr;
  const Status st = intersection_verdict(test, true);
  return st.ok() || fail(st);
}

// The verdict of the test beside if it has ended (await_intersections, which
// then does not wait); true while it runs.
bool Pipeline::take_ended_test() {
  return !pending_test_ || !pending_test_->finished() || await_intersections();
}

// The Read phase: input checks the readers also run (for PLCs built in
// code), the flat-face merge, and the exact self-intersection test (a CDT of
// an intersecting PLC does not exist, and the later steps would fail far
// from the cause) here or scheduled beside the steps (schedule_test).
bool Pipeline::read_phase(IntersectionTest& intersections) {
  Statistics& s = out_.stats;
  if (!begin(Phase::Read)) return false;
  Status st = check_plc_points(*plc_);
  const bool merging = st.ok() && merge_flat_faces();
  schedule_test(merging);
  // With the checks beside, check_plc's other checks run there (they end
  // before the order search uses the segments; see run()).
  if (st.ok() && !checks_beside_) st = check_plc(*plc_);
  if (st.ok() && opt_.quality.enabled) st = check_quality_options(opt_.quality);
  if (st.ok() && opt_.check_intersections && !test_beside_) {
    intersections.start(input_, false);
    st = intersection_verdict(intersections, false);
  }
  if (st.ok() && opt_.check_intersections && test_beside_ && !test_after_d0_) {
    intersections.start(input_, true, &intersecting_, checks_beside_);
    pending_test_ = &intersections;
  }
  // The steps mesh the merged PLC; the test above read the input, and its
  // errors (like the checks') name input facets already.
  if (st.ok() && merging) plc_ = &merged_;
  if (!st.ok()) rep_.clear();
  return end(Phase::Read, st, &s.ms_read);
}

// merge_flat_facets of the input into merged_ (Options::keep_triangles off);
// true when some facets were joined (rep_ then maps merged facets back).
bool Pipeline::merge_flat_faces() {
  out_.flat_faces_merged = !opt_.keep_triangles;
  if (opt_.keep_triangles) return false;
  Statistics& s = out_.stats;
  std::vector<uint32_t> into;
  s.merged_facets = merge_flat_facets(*plc_, merged_, into, &s.flat_edges, &insides_);
  if (s.merged_facets == 0) {
    merged_ = Plc();
    insides_ = FlatFaceInsides();
  } else {
    rep_.assign(merged_.facets.size(), kNone);
    for (uint32_t f = 0; f < into.size(); ++f)
      if (rep_[into[f]] == kNone) rep_[into[f]] = f;
  }
  out_.flat_face_of.resize(into.size());
  for (uint32_t f = 0; f < into.size(); ++f) out_.flat_face_of[f] = rep_.empty() ? f : rep_[into[f]];
  return !rep_.empty();
}

// Where the self-intersection test runs. Beside the steps on a large PLC
// (it reads the input, which the steps then share): beside step 1 when step
// 1 takes one core (small PLCs), after it when it takes both
// (DelaunayOptions::threads). Beside step 1 on one core, the rest of
// check_plc and the list of segments go to the second thread too, ahead of
// the test: step 1 needs the points alone, so that work leaves the main
// thread. The search for the perturbation order waits for them after
// D0, and a failed check is the run's error as before (with quality
// options, whose error comes after check_plc's, all checks stay here). The
// test reads the input (input_), and its errors name input facets and
// vertices; the steps of a merged PLC need the checks' verdict before the
// merge is used, so then the checks stay here.
void Pipeline::schedule_test(bool merging) {
  test_beside_ = opt_.threads && plc_->facets.size() >= kMinFacetsBeside;
  test_after_d0_ = plc_->points.size() >= kMinTwoThreadDelaunayPoints;
  checks_beside_ = opt_.check_intersections && test_beside_ && !test_after_d0_ &&
                   !opt_.quality.enabled && !merging;
}

// The perturbation order that keeps the most segments in D0 (sos_order.hpp).
// Choosing the symbolic perturbation is step 3's work in this design, so its
// time is msDegeneracy; the one tetrahedralization it hands on as D0 counts
// as step 1 (msDelaunay).
void Pipeline::choose_order(IntersectionTest& intersections) {
  if (plc_->points.size() > kMaxSosOrderPoints) return;
  const auto t0 = Clock::now();
  SosOrderStats os;
  const SegmentsWhenReady ready = [&intersections](std::vector<std::array<VertexId, 2>>& segs) {
    return intersections.checked(&segs).ok();
  };
  order_ = segment_friendly_order(*plc_, kSosOrderRounds, d0_, &os, &input_segments_, opt_.threads,
                                  checks_beside_ ? &ready : nullptr);
  if (!order_.empty()) {
    input_segments_.clear();  // numbered for the points before the order
    permute_plc(*plc_, order_, permuted_);
    plc_ = &permuted_;
    std::vector<VertexId> id_of(order_.size());
    for (size_t k = 0; k < order_.size(); ++k) id_of[order_[k]] = static_cast<VertexId>(k);
    for (auto& inner : insides_.vertices)
      for (VertexId& v : inner) v = id_of[v];
  }
  ms_d0_ = d0_.live_tets > 0 ? os.ms_d0 : 0;
  ms_order_ = ms_since(t0) - ms_d0_;
}

// With the checks beside (schedule_test): their verdict, and the segments
// they listed for step 2 when the order kept the input's numbering. Then
// step 1 here when the order search did not build it, and the test beside
// the rest when it waited for step 1's two threads.
bool Pipeline::after_order(IntersectionTest& intersections) {
  if (checks_beside_) {
    const Status checked = intersections.checked();
    if (!checked.ok()) {
      pending_test_ = nullptr;  // no test follows failed checks
      return fail(checked);
    }
    if (order_.empty()) initial_segments_ = intersections.take_segment_set();
  }
  // Of a merged PLC the input tells: its inner vertices are the merged
  // facets' insides (seeded in mesh_steps), unless a segment lies inside a
  // merged facet (an edge where a third facet stands).
  const Plc& loops_of = rep_.empty() ? *plc_ : input_;
  nothing_embedded_ = opt_.check_intersections && insides_.segments == 0 &&
                      loops_of.segments.empty() && all_points_on_loops(loops_of);
  if (opt_.check_intersections && test_beside_) {
    const auto t0 = Clock::now();
    if (d0_.live_tets == 0 &&
        !delaunay_tetrahedralize(d0_, &plc_->points[0].x, plc_->points.size(), nullptr, nullptr,
                                 delaunay_options())
             .ok())
      d0_ = TetMesh();  // step 1 runs again below and reports why
    ms_d0_ += ms_since(t0);
    if (test_after_d0_) {
      intersections.start(input_, true, &intersecting_);
      pending_test_ = &intersections;
    }
  }
  return true;
}

void Pipeline::run() {
  const auto t_total = Clock::now();
  Statistics& s = out_.stats;
  s.input_points = plc_->points.size();
  s.input_facets = plc_->facets.size();
  IntersectionTest intersections;
  if (!read_phase(intersections)) return;
  choose_order(intersections);
  if (!after_order(intersections)) return;

  // Steps 1-4. Never fail on a valid PLC: when facet recovery gives up on a
  // missing region (cavity retetrahedralization and gift-wrapping both
  // failed), a Steiner point inside the failing subface joins its facet and
  // the steps run again from the Delaunay tetrahedralization (the point is
  // in the vertex set from the start, so steps 1-4 stay exactly as the
  // paper describes them, for a PLC with one more facet vertex).
  for (;;) {
    FacetRecoveryStats fst;
    if (mesh_steps(fst)) break;
    if (!await_intersections()) return;
    const Error& e = out_.status.error;
    const bool retry = (e.code == ErrorCode::Internal || e.code == ErrorCode::LimitReached) &&
                       fst.unrecovered_facet != kNone && facet_splits_.size() < kMaxFacetSplits;
    if (!retry) return;
    add_facet_split(fst);
    out_.status = Status();
  }
  if (!await_intersections()) return;  // a run stopped before step 4
  s.facet_splits = facet_splits_.size();

  // Carving, or the intermediate mesh of a stopped run (all real tets).
  if (opt_.stop_after < Phase::Carve) {
    std::vector<TetId> tets;
    for (TetId t = 0; t < mesh_.num_tet_slots(); ++t)
      if (!mesh_.is_dead(t) && !mesh_.is_ghost(t)) tets.push_back(t);
    mesh_to_result(tets, nullptr, nullptr);
  } else {
    if (!begin(Phase::Carve)) return;
    CarveResult carved;
    Status st = carve(*plc_, mesh_, subfaces_, opt_.keep_convex_hull, carved, &subface_hf_);
    // Flat tets are flipped away only where carving keeps them; the flips
    // stay inside regions, so carving again gives the same regions.
    FlatFlipStats ff;
    if (st.ok()) {
      std::vector<uint8_t> kept(mesh_.num_tet_slots(), 0);
      for (TetId t : carved.tets) kept[t] = 1;
      remove_flat_tets(mesh_, subfaces_, segs_, &ff, &kept);
    }
    if (st.ok() && ff.flips > 0) {
      carved = CarveResult();
      st = carve(*plc_, mesh_, subfaces_, opt_.keep_convex_hull, carved, &subface_hf_);
    }
    s.flat_flips = ff.flips;
    // remove_flat_tets counted the flat tets it left among the kept ones.
    if (st.ok() && ff.remaining > 0 &&
        move_flat_tets_outside(mesh_, segs_, carved, subfaces_) > 0) {
      carved = CarveResult();
      st = carve(*plc_, mesh_, subfaces_, opt_.keep_convex_hull, carved, &subface_hf_);
    }
    if (st.ok() && ff.remaining > 0 && opt_.keep_convex_hull)
      s.flat_peeled = peel_flat_hull_tets(mesh_, subfaces_, carved, &subface_hf_);
    if (st.ok() && !opt_.keep_convex_hull) st = check_open_facets(carved);
    if (st.ok()) mesh_to_result(carved.tets, &carved.attribute, &carved);
    if (!end(Phase::Carve, st, &s.ms_carve)) return;
  }
  quality_statistics(out_.mesh, s, opt_.threads);
  s.min_dihedral_before = s.min_dihedral;
  s.radius_edge_histogram_before = s.radius_edge_histogram;
  s.dihedral_histogram_before = s.dihedral_histogram;
  if (refining()) {
    if (!begin(Phase::Refine)) return;
    const Status st = refine_quality(*plc_, opt_.quality, opt_.cancel, {&Pipeline::refine_progress, this}, out_);
    if (!end(Phase::Refine, st, &s.ms_refine)) return;
    quality_statistics(out_.mesh, s, opt_.threads);
  }
  s.ms_total = ms_since(t_total);
  done_ = true;
}

// The working mesh and the structures of the steps, freed once the Result
// holds the mesh: the validator reads only the input and the Result, and
// its sorted faces and edges of every tet then reuse the working mesh's
// memory instead of adding to it (the WebAssembly heap's 4 GiB bound the
// models the page can mesh and validate).
void Pipeline::release_work() {
  mesh_ = TetMesh();
  d0_ = TetMesh();
  segs_ = SegmentSet();
  initial_segments_ = SegmentSet();
  subfaces_ = Subfaces();
  std::vector<HalfFace>().swap(subface_hf_);
  std::vector<std::vector<VertexId>>().swap(facet_interior_);
  std::vector<VertexId>().swap(volume_points_);
  std::vector<FacetSplit>().swap(facet_splits_);
  insides_ = FlatFaceInsides();
}

// After run(): the Result in input numbering (points, facets, segments),
// validated against the input (validate() merges flat faces as the run did:
// Result::flat_faces_merged), since its messages name input vertices.
void Pipeline::finish(const Plc& input) {
  // The Result holds the mesh now: the steps' structures go first, so that
  // the segment lists report_input_ids makes (every edge of the input) and
  // the validator's sorted faces and edges reuse their memory instead of
  // adding to the peak.
  release_work();
  report_input_ids(input);
  if (!done_) return;
  if (opt_.validate && opt_.stop_after >= Phase::Carve) {
    Status v = validate(input, out_);
    if (!v.ok()) {
      out_.status = v;
      return;
    }
  }
  progress(Phase::Done, 1);
}

}  // namespace

Status delaunay_tetrahedralization(const std::vector<double>& xyz, std::vector<uint32_t>& tets,
                                   double* ms) {
  const auto t0 = Clock::now();
  tets.clear();
  if (xyz.size() % 3 != 0)
    return make_error(ErrorCode::InvalidArgument, "Points need 3 coordinates each.");
  TetMesh mesh;
  // One thread, the tets as made (their order does not matter here).
  DelaunayOptions options;
  options.canonical = false;
  Status st = delaunay_tetrahedralize(mesh, xyz.data(), xyz.size() / 3, nullptr, nullptr, options);
  if (!st.ok()) return st;
  tets.reserve(4 * mesh.num_real_tets());
  for (TetId t = 0; t < mesh.num_tet_slots(); ++t)
    if (!mesh.is_dead(t) && !mesh.is_ghost(t))
      for (int k = 0; k < 4; ++k) tets.push_back(mesh.vertex(t, k));
  if (ms) *ms = ms_since(t0);
  return st;
}

Status triangulate_surface(const Plc& plc, std::vector<uint32_t>& triangles,
                           std::vector<uint32_t>& triangle_facet) {
  triangles.clear();
  triangle_facet.clear();
  TetMesh points;  // coordinates only: triangulate_facets reads no tets
  points.reserve(plc.points.size(), 0);
  for (const Vec3& p : plc.points) points.add_vertex(&p.x, kVertexInput);
  SegmentSet unsplit;
  init_segments(plc, unsplit);
  Subfaces sub;
  Status st = triangulate_facets(plc, unsplit, points, {}, sub);
  if (!st.ok()) return st;
  triangles.reserve(3 * sub.tri.size());
  for (const auto& t : sub.tri) triangles.insert(triangles.end(), t.begin(), t.end());
  triangle_facet = sub.facet;
  return st;
}

Result tetrahedralize(const Plc& plc, const Options& options) {
  Result out;
  if (plc.points.size() >= (1u << 30) || plc.facets.size() >= (1u << 30)) {
    out.status.error = {ErrorCode::TooLarge, "The PLC has more than 2^30 points or facets.",
                        plc.file};
    return out;
  }
  // The core never throws: an allocation failure (the only exception the
  // standard library raises here) becomes an error. In WebAssembly builds
  // without exception support, memory growth failure aborts instead; the JS
  // wrapper reports that as out-of-memory.
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
  try {
    Pipeline p(plc, options, out);
    p.run();
    p.finish(plc);
  } catch (...) {  // catch (...): see current_exception_code()
    out = Result();
    out.status.error = current_exception_error("meshing", plc.file);
  }
#else
  Pipeline p(plc, options, out);
  p.run();
  p.finish(plc);
#endif
  if (!out.status.ok() && out.status.error.file.empty()) out.status.error.file = plc.file;
  if (out.status.ok()) out.mesh.marker_names = plc.marker_names;
  return out;
}

}  // namespace cdt3d
