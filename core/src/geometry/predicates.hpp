// Exact geometric predicates on double coordinates (filter -> exact expansion
// arithmetic), plus symbolic perturbation ordered by vertex index.
// Round-to-nearest only; no FMA contraction (-ffp-contract=off); no fesetround.
//
// Each predicate is the sign of a polynomial in the coordinates. It first
// evaluates the polynomial in doubles and compares the result against a
// rigorous semi-static error bound (computed from the absolute coordinate
// differences of each column, the Meyer–Pion idea, with constants derived
// below for our exact evaluation order). Only when the bound cannot decide
// does it call the exact stage (predicates.cpp), which evaluates the same
// polynomial with floating-point expansions (expansion.hpp) and never rounds.
// The filters are valid for any finite or non-finite input (they defer to
// the exact stage outside their own limits); the range below concerns the
// exact stage only.
//
// Supported range (exactness guarantee). Every predicate returns the sign of
// the exact real determinant when each coordinate of the points involved is
// 0 or has magnitude in [1e-50, 1e50] (kMaxCoordinate in cdt3d.hpp). More
// generally the exact stage scales the points by a power of two so that no
// partial product can overflow or lose bits below 2^-1074; this works when
// hi - lo <= 404 for insphere (508 incircle, 678 orient3d, 1027 orient2d),
// where 2^hi bounds the largest |coordinate| and 2^lo is the lowest set bit
// of any nonzero coordinate. For |x| in [1e-50, 1e50]: hi <= 167 and
// lo >= -219 (ulp of 2^-167), so hi - lo <= 386 (the auxiliary point of
// incircle_coplanar adds at most one bit to hi). Points outside this rule
// (for instance a subnormal coordinate next to a coordinate of 1) still get
// an answer, usually right but not guaranteed, and counters().out_of_range
// counts them.
#pragma once

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <initializer_list>

#if defined(__FAST_MATH__)
#error "cdt3d predicates need IEEE arithmetic: never compile with -ffast-math or -Ofast"
#endif
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0
#error "cdt3d predicates need doubles evaluated in double precision (FLT_EVAL_METHOD == 0)"
#endif

// The filters' expression trees, and the filters of the conflict tests of
// point insertion (*_in_box, *_small_integers), are inlined into every
// caller, where the compiler keeps the terms in registers and drops the ones
// a caller does not read. GCC does so on its own; clang (the WebAssembly
// build) kept insphere_terms out of line, returning all 20 terms through
// memory on each of the dozens of conflict tests per inserted point, and
// then insphere_in_box.
#if defined(__GNUC__) || defined(__clang__)
#define CDT3D_FILTER_INLINE inline __attribute__((always_inline))
#else
#define CDT3D_FILTER_INLINE inline
#endif

#ifndef CDT3D_PREDICATE_CALL_COUNTS
#if defined(__EMSCRIPTEN__)
#define CDT3D_PREDICATE_CALL_COUNTS 0
#else
#define CDT3D_PREDICATE_CALL_COUNTS 1
#endif
#endif

namespace cdt3d {
namespace pred {

/// Sign of the determinant | ax-dx ay-dy az-dz ; bx-dx ... ; cx-dx ... |.
/// > 0 when d lies below the plane through a, b, c, with a, b, c appearing
/// counterclockwise seen from above (Shewchuk's convention). Exact.
inline int orient3d(const double* a, const double* b, const double* c, const double* d);

/// Sign of the 2D orientation of (a, b, c): > 0 counterclockwise. Exact.
inline int orient2d(const double* a, const double* b, const double* c);

/// Sign of orient2d of the projections of 3D points a, b, c onto the
/// coordinate plane that drops axis `drop` (0 = x, 1 = y, 2 = z); the
/// remaining axes are taken in cyclic order (drop 0: (y,z), 1: (z,x), 2: (x,y)),
/// so for points in a plane with normal n, the sign equals sign(n[drop]) times
/// the in-plane orientation. Exact (projection drops a coordinate, no rounding).
int orient2d_projected(const double* a, const double* b, const double* c, int drop);

/// Sign of the insphere determinant: > 0 when e lies inside the sphere through
/// a, b, c, d, provided orient3d(a, b, c, d) > 0 (the sign flips otherwise).
/// Exact, unperturbed (0 when co-spherical).
inline int insphere(const double* a, const double* b, const double* c, const double* d,
                    const double* e);

/// Points whose coordinates are all integers of magnitude below 2^52 and
/// spread over at most this much on each axis: on them orient3d and
/// insphere evaluated in doubles are exact (every coordinate difference is
/// then an integer M <= 2^9, the bound of the proof at kInsphereSmallInteger
/// below, and of kOrient3dSmallInteger = 2^16).
inline constexpr double kSmallIntegerSpread = 0x1p+9;
/// Whether the n points (3 coordinates each) are such points.
bool small_integer_points(const double* coords, size_t n);
/// orient3d and insphere for such points (small_integer_points): the double
/// evaluation is the exact determinant, so no filter and no exact stage.
/// Wrong answers for other points.
CDT3D_FILTER_INLINE int orient3d_small_integers(const double* a, const double* b, const double* c,
                                                const double* d);
CDT3D_FILTER_INLINE int insphere_small_integers(const double* a, const double* b, const double* c,
                                                const double* d, const double* e);

/// Static error bounds of orient3d and insphere for points that all lie in
/// one box (Meyer-Pion's static filters): the box's widths bound every
/// coordinate difference a call can compute, so one bound, computed once,
/// serves every call on those points, and a call evaluates its determinant
/// alone, without the column sums of its semi-static bound (*_in_box below).
/// A bound is 0 when the box is outside the range where it is proven
/// (derivations at kOrient3dBoxEps and kInsphereBoxEps); the *_in_box
/// predicates then never decide by it.
struct BoxBounds {
  double orient3d = 0, insphere = 0;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  ///< the box
  /// Whether p lies in the closed box.
  bool contains(const double* p) const {
    return (lo[0] <= p[0]) & (p[0] <= hi[0]) & (lo[1] <= p[1]) & (p[1] <= hi[1]) &
           (lo[2] <= p[2]) & (p[2] <= hi[2]);
  }
};
/// The bounds for the box of the n points in `coords`, widened on each side
/// by `widen` times its width (room for points constructed later near the
/// hull of these, on segments between them, say; a caller checks each such
/// point with contains()).
BoxBounds box_bounds(const double* coords, size_t n, double widen = 0);
/// orient3d and insphere for points inside the box of `bounds`: decided by
/// the static bound when it can, by orient3d() / insphere() otherwise. Wrong
/// answers for points outside the box.
CDT3D_FILTER_INLINE int orient3d_in_box(const double* a, const double* b, const double* c,
                                        const double* d, const BoxBounds& bounds);
CDT3D_FILTER_INLINE int insphere_in_box(const double* a, const double* b, const double* c,
                                        const double* d, const double* e, const BoxBounds& bounds);

/// 2D incircle: > 0 when d inside the circle through a, b, c with
/// orient2d(a,b,c) > 0. Exact.
int incircle(const double* a, const double* b, const double* c, const double* d);

/// In-plane incircle for four coplanar 3D points, without rounding any
/// projection: > 0 when d is inside the circumcircle of a, b, c, independent of
/// the orientation of a, b, c. Precondition: a, b, c not collinear and d in
/// their plane. Exact. (Evaluated as insphere(a, b, c, f, d) for a point f off
/// the plane with exact double coordinates: the sphere through a, b, c, f
/// meets the plane in the circumcircle; 0 if a, b, c are collinear.)
int incircle_coplanar(const double* a, const double* b, const double* c, const double* d);

/// Sign of (a - v) . (b - v), exact: > 0 when the angle avb is acute, 0 when
/// right, < 0 when obtuse; <= 0 exactly when v lies in the closed ball with
/// diameter ab (v encroaches upon the segment ab, §5).
int dot_sign(const double* a, const double* v, const double* b);
/// Sign of (a - v) . (b - w), exact (the same evaluation): with w = v the
/// above; (x - y) . (b - a) orders x and y along the line ab.
int dot_sign(const double* a, const double* v, const double* b, const double* w);

/// Sign of orient2d_projected(a, b, m, drop) for the centroid m of c[0..2],
/// without constructing m: orient2d is affine in its last point, so this is
/// the sign of the sum of the three orientations, evaluated exactly.
int orient2d_centroid_projected(const double* a, const double* b, const double* const c[3], int drop);

/// Sign of orient3d(a, b, c, m) for the centroid m of p[0..2], without
/// constructing m (orient3d is affine in its last point: the sign of the sum
/// of the three orientations, evaluated exactly).
int orient3d_centroid(const double* a, const double* b, const double* c, const double* const p[3]);

/// Collinearity of three 3D points, exact.
bool collinear3d(const double* a, const double* b, const double* c);

/// The order of the symbolic perturbation: true when vertex id x gets a
/// larger infinitesimal raise of its lifted coordinate than id y (x's raise
/// decides a tie first). The smallest id is raised most, so the newest
/// vertices (Steiner points have the largest ids) are raised least and win
/// ties: a Steiner point inserted to split a segment keeps the edges it was
/// inserted for when it is co-spherical with older vertices, which is what
/// segment recovery needs (fewer further splits on CAD inputs). Every SoS
/// decision in the library (sos.cpp, the 2D facet triangulation, the facet
/// diagonal flips) orders by this one function.
inline bool sos_raised_before(uint32_t x, uint32_t y) { return x > y; }
/// The id among a, b, c, d whose raise decides first (sos_raised_before).
inline uint32_t sos_first(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  uint32_t m = a;
  for (uint32_t x : {b, c, d}) if (sos_raised_before(x, m)) m = x;
  return m;
}
/// Symbolically perturbed insphere (Simulation of Simplicity on the lifted
/// points, ordered by the vertex ids ia..ie, which must be distinct). Never 0
/// when a,b,c,d is a proper tetrahedron with orient3d(a,b,c,d) > 0:
/// > 0 inside, < 0 outside. Uses insphere() first; the perturbation only
/// decides exact zeros.
/// The perturbation: the lifted coordinate |p|^2 of each point is raised by
/// eps^(k), k = 1 for the first id in sos_raised_before order, 2 for the
/// next, ...; so on a tie that point counts as slightly farther out, and the
/// query e is outside when it comes first. See sos.cpp for the derivation.
int insphere_sos(const double* a, const double* b, const double* c, const double* d,
                 const double* e, uint32_t ia, uint32_t ib, uint32_t ic, uint32_t id, uint32_t ie);
/// insphere_sos for a caller that already has insphere(a, b, c, d, e) == 0:
/// the perturbation alone, without evaluating the exact zero a second time
/// (co-spherical CAD points reach this often, and the exact zero is the
/// costly part). With `small_integers` the points must pass
/// small_integer_points, and its orientations are evaluated in doubles
/// (orient3d_small_integers).
int insphere_tie(const double* a, const double* b, const double* c, const double* d,
                 const double* e, uint32_t ia, uint32_t ib, uint32_t ic, uint32_t id, uint32_t ie,
                 bool small_integers = false);

/// Perturbed "in circle of a hull face" test used for ghost tets: for e coplanar
/// with a, b, c (orient3d == 0), decides whether e is in conflict with the
/// ghost tet on the outer side of face (a, b, c), consistently with
/// insphere_sos. > 0 conflict.
/// Convention (tet_mesh.hpp): the ghost tet is (a, b, c, infinity) and the
/// outer side is where orient3d(a, b, c, p) > 0. Its "sphere" is the limit of
/// the sphere through a, b, c and a point q going to infinity on that side:
/// the open outer half-space plus the open disk of the circumcircle of a, b, c.
/// So: orient3d(a, b, c, e) != 0 gives the answer (> 0 conflict); otherwise
/// incircle_coplanar(a, b, c, e) != 0 does; otherwise (e on the circle) the
/// answer is insphere_sos(a, b, c, q, e) for any such q, which no longer
/// depends on q nor on the id of the infinite vertex (sos.cpp). Never 0 when
/// a, b, c are not collinear.
int incircle_coplanar_sos(const double* a, const double* b, const double* c, const double* e,
                          uint32_t ia, uint32_t ib, uint32_t ic, uint32_t ie);
/// incircle_coplanar_sos for a caller that already has orient3d(a, b, c, e)
/// == 0 (again without a second exact evaluation of that zero).
/// With `small_integers` the points must pass small_integer_points
/// (incircle_coplanar_small_integers).
int incircle_coplanar_sos_on_plane(const double* a, const double* b, const double* c,
                                   const double* e, uint32_t ia, uint32_t ib, uint32_t ic,
                                   uint32_t ie, bool small_integers = false);
/// incircle_coplanar for points that pass small_integer_points. Four points
/// in one axis-parallel plane (the hull faces of grid and CAD models, which
/// the ghost tets of every co-spherical cell test) are decided in doubles:
/// with integer coordinate differences of at most 2^9 the projected
/// determinant's products and sums are integers below 2^40, so its double
/// evaluation is exact, zeros included (those co-circular zeros would
/// otherwise each go to incircle's exact stage). Other planes go to
/// incircle_coplanar.
int incircle_coplanar_small_integers(const double* a, const double* b, const double* c,
                                     const double* d);

/// Counters for filter efficiency, one set per thread (the pipeline may run
/// its self-intersection test on a second thread); for statistics only.
/// *_exact counts the calls the filter could not decide (always on).
/// *_calls counts every call when CDT3D_PREDICATE_CALL_COUNTS is 1, the
/// default natively; in WebAssembly builds the default is 0 and they stay 0,
/// because under V8 the per-call memory increment costs as much as the
/// whole filter. Define CDT3D_PREDICATE_CALL_COUNTS=1 to force them on.
struct Counters {
  uint64_t orient3d_calls = 0, orient3d_exact = 0;
  uint64_t insphere_calls = 0, insphere_exact = 0;
  uint64_t orient2d_calls = 0, orient2d_exact = 0;
  uint64_t incircle_calls = 0, incircle_exact = 0;
  uint64_t sos_ties = 0;      ///< insphere_sos / incircle_coplanar_sos decided by SoS
  uint64_t out_of_range = 0;  ///< exact evaluations outside the supported range

  /// Adds another thread's counts.
  Counters& operator+=(const Counters& o) {
    orient3d_calls += o.orient3d_calls, orient3d_exact += o.orient3d_exact;
    insphere_calls += o.insphere_calls, insphere_exact += o.insphere_exact;
    orient2d_calls += o.orient2d_calls, orient2d_exact += o.orient2d_exact;
    incircle_calls += o.incircle_calls, incircle_exact += o.incircle_exact;
    sos_ties += o.sos_ties, out_of_range += o.out_of_range;
    return *this;
  }
};

namespace detail {

extern thread_local Counters g_counters;

inline void count_call(uint64_t& counter) {
#if CDT3D_PREDICATE_CALL_COUNTS
  ++counter;
#else
  (void)counter;
#endif
}

// Exact stages (predicates.cpp); they count themselves in g_counters.
int orient3d_exact(const double* a, const double* b, const double* c, const double* d);
int insphere_exact(const double* a, const double* b, const double* c, const double* d,
                   const double* e);
int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);
// P of insphere's second stage (below): its determinant's expression tree
// on absolute values (the same tree on purpose: the bound counts its
// roundings), from the rows A..D (a..d minus e) and their lifts as computed
// there.
double insphere_permanent(const double (&rows)[4][3], const double (&lifts)[4]);
inline int orient2d_xy(double ax, double ay, double bx, double by, double cx, double cy);

// Filter constants. Notation: u = 2^-53 (unit roundoff); fl(x op y) =
// (x op y)(1 + t) with |t| <= u as long as nothing underflows. The computed
// coordinate differences D' = fl(p - q) satisfy |D - D'| <= u |D'| (half an
// ulp of the result; differences that land in the subnormal range are exact).
//
// The polynomial is evaluated by a fixed expression tree. Expanded into
// monomials of the D', the computed value is sum(m * prod(1 + t)) with at most
// k factors on each monomial, k being the number of roundings on the longest
// leaf-to-root path (products contribute the paths of both operands plus
// one). Replacing D' by the exact D adds one factor (1 + t) per factor of the
// monomial (its degree g). Hence
//     |computed - exact| <= ((1 + u)^(k + g) - 1) * S,   S = sum |m|,
// and S is bounded through the column maxima M_x = max |D'_x| over the rows.
// The filter uses the column sums s_x = fl(sum |D'_x|) instead, which are at
// least M_x (rounding is monotonic and M_x is a double) and at most
// n M_x (1 + nu) for n rows: no comparisons or selects, which matters in
// WebAssembly, where V8 turns each f64 select or max into a branch that
// mispredicts on random data.
// The bound actually tested is computed in doubles (a few more factors
// (1 - u)) and its constant is rounded up with a margin (>= 0.09u of S); the
// margin also absorbs the absolute error of underflowing products (each at
// most 2^-1075, times at most the product of the remaining factors), which is
// why the filter requires every s >= kLo (so every M >= kLo / n / (1 + nu)):
// that keeps the margin above it and keeps the bound a normal number (for
// orient3d/orient2d a single test on the product of the sums suffices).
// s_x + s_y + s_z <= kHi bounds every entry and rules out overflow (and
// catches inf/NaN, since comparisons with NaN are false). Outside those
// limits, or when |computed| <= bound, the exact stage decides.
//
// orient3d: det = Ax(ByCz - BzCy) + Bx(CyAz - CzAy) + Cx(AyBz - AzBy),
//   summed left to right: k = 5 (mul, sub, mul, add, add), g = 3;
//   S <= 6 Mx My Mz (six monomials |x y z|); (1+u)^8 - 1 < 8.0000001u;
//   48u(1 + 1e-6) = 5.3291e-15 < 5.34e-15 (margin 0.098u).
//   Underflow needs only one test here: with every entry <= 2^300 the at most
//   9 products err by <= 2^-1075 (6 * 2^300 * 1.01 + 3) < 2^-772 in all,
//   below the margin 0.098u P once P = fl(fl(sx sy) sz) >= 2^-700; and then
//   sx sy >= 2^-700 / 2^302 did not underflow, nor does the bound.
inline constexpr double kOrient3dEps = 5.34e-15;
inline constexpr double kOrient3dLo = 0x1p-700, kOrient3dHi = 0x1p+300;
// insphere (rows A..D = a..d minus e, lifts l = Ax^2 + Ay^2 + Az^2):
//   det = (ld*abc - lc*dab) + (lb*cda - la*bcd), 3x3 minors from 2x2 xy
//   minors as in the code: minor path 5, lift path 3, product 1, two more
//   sums: k = 11, g = 5; S = sum_i l_i * perm3(other rows) <= 6 Mx My Mz
//   (la + lb + lc + ld); (1+u)^16 - 1 < 16.0000001u; 96u(1 + 11u) <
//   1.06582e-14 < 1.07e-14 (margin 0.37u). The sum of the lifts used in the
//   bound is computed, (1 - u)^-6 covered by the margin.
//   Underflow: about 40 products, each error amplified by at most 7 Mmax^3
//   (a lift times a z, or a 3x3 minor); sum(l) >= Mmax^2, so once every
//   M >= 2^-189 (s >= 2^-187; then Mmin^5 * 2^-47 > 2^-1022: bound normal)
//   the margin 0.37u Mx My Mz sum(l) dominates.
inline constexpr double kInsphereEps = 1.07e-14;
inline constexpr double kInsphereLo = 0x1p-187, kInsphereHi = 0x1p+200;
// Second stage, run only when a filter fails (insphere_permanent, incircle in
// predicates.cpp): the same error bound with S computed instead of bounded
// by column sums. P = fl(the expression tree with every difference and
// product replaced by its absolute value and every subtraction by an
// addition) expands to sum(|m| prod(1 + t)) with at most k factors, so S <=
// P (1 - u)^-k. On thin and flat configurations (CAD models: long thin tets,
// points along a segment, co-spherical neighbours) S lies far below the
// column-sum bound, and this stage decides what the exact stage would
// otherwise evaluate in microseconds.
//   insphere: ((1+u)^16 - 1)(1-u)^-11 < 16.0000001u (1 + 11.01u) < 16.1u, and
//   fl(C P) loses one more (1 - u): C = 1.9e-15 (17.1u).
//   Underflow: under the first stage's limits (every s >= kInsphereLo, the
//   sum <= kInsphereHi) the products of det and of P err by < 2^-466 in
//   all (40 products, each error <= 2^-1075 amplified by <= 7 (2^200)^3);
//   requiring P >= 2^-400 keeps the margin 0.9u P above that.
inline constexpr double kInspherePermanentEps = 1.9e-15;
inline constexpr double kInspherePermanentLo = 0x1p-400;
// Static bounds (box_bounds): for points inside a box of widths W_x, W_y,
// W_z, every computed difference satisfies |D'_x| <= fl(hi_x - lo_x) = W_x
// (exact |D_x| <= hi_x - lo_x, and rounding is monotonic), so M_x <= W_x.
//   orient3d: with the same k = 5, g = 3, S <= 6 Wx Wy Wz and the error is
//   below 48.0000006u Wx Wy Wz = 5.3290706e-15 (...); the constant 5.34e-15
//   leaves a margin of 0.2% of the bound for its own evaluation (two
//   roundings) and for underflow.
//   insphere: each lift l_i <= W_x^2 + W_y^2 + W_z^2 (the exact lifts of the
//   D', as in the derivation above), so S <= 6 Wx Wy Wz * 4 (Wx^2 + Wy^2 +
//   Wz^2); with k = 11, g = 5 the error is below 16.0000001u S =
//   384.0000024u Wx Wy Wz (Wx^2 + Wy^2 + Wz^2) = 4.2632565e-14 (...); the
//   constant 4.27e-14 leaves a margin of 0.16% of the bound for its own
//   evaluation (six roundings) and for underflow.
//   Underflow: with every width in [2^-100, 2^100] the orient3d bound is >=
//   2^-348 and the insphere bound >= 2^-545, while the products of the
//   determinants err by at most 2^-1075 each, amplified by at most 7
//   (2^100)^3: in all < 2^-766, far below either margin; nothing overflows
//   (|det| <= 72 W^5 <= 2^507). Outside that range both bounds are 0.
inline constexpr double kOrient3dBoxEps = 5.34e-15;
inline constexpr double kInsphereBoxEps = 4.27e-14;
inline constexpr double kBoxWidthLo = 0x1p-100, kBoxWidthHi = 0x1p+100;
// orient2d: det = Ax By - Ay Bx: k = 2, g = 2, S <= 2 Mx My;
//   8u(1 + 1e-6) = 8.8818e-16 < 9e-16 (margin 0.1u); as for orient3d, one
//   test P = fl(sx sy) >= 2^-900 (the two products err by <= 2^-1074 in all).
inline constexpr double kOrient2dEps = 9.0e-16;
inline constexpr double kOrient2dLo = 0x1p-900, kOrient2dHi = 0x1p+500;

inline int sign_of(double x) { return (x > 0.0) - (x < 0.0); }
// Exact evaluation for integer coordinates. When every coordinate is an
// integer of magnitude below 2^52, every coordinate difference D is an
// integer computed exactly, and each product and sum of the expression trees
// above is an integer; it is computed exactly while its magnitude stays
// below 2^53. With M = max |D| <= sx + sy + sz:
//   orient3d: 2x2 minors <= 2 M^2, terms <= 2 M^3, det <= 6 M^3; M <= 2^16
//     gives 6 * 2^48 < 2^53.
//   insphere: 2x2 minors <= 2 M^2, 3x3 minors <= 6 M^3, lifts <= 3 M^2,
//     products <= 18 M^5, det <= 72 M^5; M <= 2^9 gives 72 * 2^45 < 2^53.
// The sums sx, sy, sz are exact too (integers far below 2^53), so the test
// sx + sy + sz <= bound is exact.
inline constexpr double kOrient3dSmallInteger = 0x1p+16;
inline constexpr double kInsphereSmallInteger = 0x1p+9;
// 1 when all given coordinate differences are zero (pass 0 for unused
// slots), else 0; an int, so that callers combine columns with | and no
// branch (as the filters do).
inline int zero_column(double p, double q, double r, double s) {
  return static_cast<int>(p == 0) & static_cast<int>(q == 0) & static_cast<int>(r == 0) &
         static_cast<int>(s == 0);
}
// x is an integer below 2^52 in magnitude. The round trip through int64_t
// is one conversion each way (std::trunc is a libm call on baseline x86-64,
// and the small-integer test ran on every tie of grid models); the range
// test comes first, so the conversion is defined (NaN fails it).
inline bool small_integer(double x) {
  return std::fabs(x) < 0x1p+52 && x == static_cast<double>(static_cast<int64_t>(x));
}
inline bool integers(std::initializer_list<const double*> points) {
  bool ok = true;
  for (const double* p : points)
    for (int k = 0; k < 3; ++k) ok = ok && small_integer(p[k]);
  return ok;
}

// The first stages' values of orient3d (the filter's inputs), computed by one
// expression tree wherever they are needed, so that the out-of-line rest
// (orient3d_undecided) sees the very doubles the inline filter saw.
struct Orient3dTerms {
  double adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz, det, sx, sy, sz;
};
CDT3D_FILTER_INLINE Orient3dTerms orient3d_terms(const double* a, const double* b, const double* c,
                                                 const double* d) {
  Orient3dTerms t;
  t.adx = a[0] - d[0], t.ady = a[1] - d[1], t.adz = a[2] - d[2];
  t.bdx = b[0] - d[0], t.bdy = b[1] - d[1], t.bdz = b[2] - d[2];
  t.cdx = c[0] - d[0], t.cdy = c[1] - d[1], t.cdz = c[2] - d[2];
  t.det = t.adx * (t.bdy * t.cdz - t.bdz * t.cdy) + t.bdx * (t.cdy * t.adz - t.cdz * t.ady) +
          t.cdx * (t.ady * t.bdz - t.adz * t.bdy);
  t.sx = (std::fabs(t.adx) + std::fabs(t.bdx)) + std::fabs(t.cdx);
  t.sy = (std::fabs(t.ady) + std::fabs(t.bdy)) + std::fabs(t.cdy);
  t.sz = (std::fabs(t.adz) + std::fabs(t.bdz)) + std::fabs(t.cdz);
  return t;
}
inline bool orient3d_decided(const Orient3dTerms& t) {
  const double p = t.sx * t.sy * t.sz;
  return (std::fabs(t.det) > kOrient3dEps * p) & (p >= kOrient3dLo) &
         (t.sx + t.sy + t.sz <= kOrient3dHi);
}

// Likewise for insphere.
struct InsphereTerms {
  double aex, aey, aez, bex, bey, bez, cex, cey, cez, dex, dey, dez;
  double la, lb, lc, ld, det, sx, sy, sz;
};
CDT3D_FILTER_INLINE InsphereTerms insphere_terms(const double* a, const double* b, const double* c,
                                                 const double* d, const double* e) {
  InsphereTerms t;
  t.aex = a[0] - e[0], t.aey = a[1] - e[1], t.aez = a[2] - e[2];
  t.bex = b[0] - e[0], t.bey = b[1] - e[1], t.bez = b[2] - e[2];
  t.cex = c[0] - e[0], t.cey = c[1] - e[1], t.cez = c[2] - e[2];
  t.dex = d[0] - e[0], t.dey = d[1] - e[1], t.dez = d[2] - e[2];
  const double ab = t.aex * t.bey - t.bex * t.aey;
  const double bc = t.bex * t.cey - t.cex * t.bey;
  const double cd = t.cex * t.dey - t.dex * t.cey;
  const double da = t.dex * t.aey - t.aex * t.dey;
  const double ac = t.aex * t.cey - t.cex * t.aey;
  const double bd = t.bex * t.dey - t.dex * t.bey;
  const double abc = t.aez * bc - t.bez * ac + t.cez * ab;
  const double bcd = t.bez * cd - t.cez * bd + t.dez * bc;
  const double cda = t.cez * da + t.dez * ac + t.aez * cd;
  const double dab = t.dez * ab + t.aez * bd + t.bez * da;
  t.la = t.aex * t.aex + t.aey * t.aey + t.aez * t.aez;
  t.lb = t.bex * t.bex + t.bey * t.bey + t.bez * t.bez;
  t.lc = t.cex * t.cex + t.cey * t.cey + t.cez * t.cez;
  t.ld = t.dex * t.dex + t.dey * t.dey + t.dez * t.dez;
  t.det = (t.ld * abc - t.lc * dab) + (t.lb * cda - t.la * bcd);
  t.sx = (std::fabs(t.aex) + std::fabs(t.bex)) + (std::fabs(t.cex) + std::fabs(t.dex));
  t.sy = (std::fabs(t.aey) + std::fabs(t.bey)) + (std::fabs(t.cey) + std::fabs(t.dey));
  t.sz = (std::fabs(t.aez) + std::fabs(t.bez)) + (std::fabs(t.cez) + std::fabs(t.dez));
  return t;
}
inline bool insphere_in_range(const InsphereTerms& t) {
  return (t.sx >= kInsphereLo) & (t.sy >= kInsphereLo) & (t.sz >= kInsphereLo) &
         (t.sx + t.sy + t.sz <= kInsphereHi);
}
inline bool insphere_decided(const InsphereTerms& t) {
  const double bound = kInsphereEps * t.sx * t.sy * t.sz * ((t.la + t.lb) + (t.lc + t.ld));
  return (std::fabs(t.det) > bound) & insphere_in_range(t);
}

// The stages after a failed filter (predicates.cpp), out of line: inlined,
// their live values made the compiler spill the filter's registers to the
// stack on every call, on the hot path of every insertion.
int orient3d_undecided(const double* a, const double* b, const double* c, const double* d);
int insphere_undecided(const double* a, const double* b, const double* c, const double* d,
                       const double* e);

}  // namespace detail

inline int orient3d(const double* a, const double* b, const double* c, const double* d) {
  detail::count_call(detail::g_counters.orient3d_calls);
  const detail::Orient3dTerms t = detail::orient3d_terms(a, b, c, d);
  if (detail::orient3d_decided(t)) return detail::sign_of(t.det);
  return detail::orient3d_undecided(a, b, c, d);
}

inline int insphere(const double* a, const double* b, const double* c, const double* d,
                    const double* e) {
  detail::count_call(detail::g_counters.insphere_calls);
  const detail::InsphereTerms t = detail::insphere_terms(a, b, c, d, e);
  if (detail::insphere_decided(t)) return detail::sign_of(t.det);
  return detail::insphere_undecided(a, b, c, d, e);
}

namespace detail {
// orient3d() and insphere() out of line, for the rare calls that a box bound
// leaves open (kept out of the callers' hot loops).
int orient3d_out_of_line(const double* a, const double* b, const double* c, const double* d);
int insphere_out_of_line(const double* a, const double* b, const double* c, const double* d,
                         const double* e);
}  // namespace detail

// The determinants of orient3d_terms and insphere_terms (the bounds count
// the roundings of those very expression trees); inlined, the compiler drops
// the column sums these callers do not read.
CDT3D_FILTER_INLINE int orient3d_in_box(const double* a, const double* b, const double* c,
                                        const double* d, const BoxBounds& bounds) {
  const double det = detail::orient3d_terms(a, b, c, d).det;
  if (std::fabs(det) > bounds.orient3d) {
    detail::count_call(detail::g_counters.orient3d_calls);
    return detail::sign_of(det);
  }
  return detail::orient3d_out_of_line(a, b, c, d);
}

CDT3D_FILTER_INLINE int insphere_in_box(const double* a, const double* b, const double* c,
                                        const double* d, const double* e, const BoxBounds& bounds) {
  const double det = detail::insphere_terms(a, b, c, d, e).det;
  if (std::fabs(det) > bounds.insphere) {
    detail::count_call(detail::g_counters.insphere_calls);
    return detail::sign_of(det);
  }
  return detail::insphere_out_of_line(a, b, c, d, e);
}

CDT3D_FILTER_INLINE int orient3d_small_integers(const double* a, const double* b, const double* c,
                                                const double* d) {
  detail::count_call(detail::g_counters.orient3d_calls);
  return detail::sign_of(detail::orient3d_terms(a, b, c, d).det);
}

CDT3D_FILTER_INLINE int insphere_small_integers(const double* a, const double* b, const double* c,
                                                const double* d, const double* e) {
  detail::count_call(detail::g_counters.insphere_calls);
  return detail::sign_of(detail::insphere_terms(a, b, c, d, e).det);
}

inline int detail::orient2d_xy(double ax, double ay, double bx, double by, double cx, double cy) {
  count_call(g_counters.orient2d_calls);
  const double acx = ax - cx, acy = ay - cy;
  const double bcx = bx - cx, bcy = by - cy;
  const double det = acx * bcy - acy * bcx;
  const double sx = std::fabs(acx) + std::fabs(bcx);
  const double sy = std::fabs(acy) + std::fabs(bcy);
  const double p = sx * sy;
  const bool decided =
      (std::fabs(det) > kOrient2dEps * p) & (p >= kOrient2dLo) & (sx + sy <= kOrient2dHi);
  if (decided) return sign_of(det);
  // Three points on one axis-parallel line: a zero column (see orient3d).
  if (zero_column(acx, bcx, 0, 0) | zero_column(acy, bcy, 0, 0)) return 0;
  // Two equal points (a computed difference is 0 exactly when the two
  // coordinates are equal; equal differences do not make equal points):
  // callers ask about triangles that share a vertex (the self-intersection
  // test), nearly all the exact calls there.
  if (zero_column(acx, acy, 0, 0) | zero_column(bcx, bcy, 0, 0) | ((ax == bx) & (ay == by)))
    return 0;
  return orient2d_exact(ax, ay, bx, by, cx, cy);
}

inline int orient2d(const double* a, const double* b, const double* c) {
  return detail::orient2d_xy(a[0], a[1], b[0], b[1], c[0], c[1]);
}

inline Counters& counters() { return detail::g_counters; }

}  // namespace pred
}  // namespace cdt3d
