// Exact predicates (predicates.hpp) against an exact rational oracle (GMP
// mpq_class): random, nearly degenerate, exactly degenerate and range-limit
// inputs; antisymmetry under permutations; Simulation of Simplicity against
// an explicitly perturbed determinant; a micro benchmark (printed only).
#include <gmpxx.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "double_double.hpp"
#include "predicates.hpp"

namespace {

using namespace cdt3d;
using P3 = std::array<double, 3>;

// ---- deterministic random numbers -----------------------------------------

struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed) {}
  uint64_t next() {  // splitmix64
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double unit() { return static_cast<double>(next() >> 11) * 0x1p-53; }  // [0, 1)
  double sym() { return 2.0 * unit() - 1.0; }                            // [-1, 1)
  int range(int lo, int hi) { return lo + static_cast<int>(next() % uint64_t(hi - lo + 1)); }
  // Random sign, random significand, magnitude in [2^e, 2^(e+1)).
  double at_exponent(int e) {
    const double x = std::ldexp(1.0 + unit(), e);
    return (next() & 1) ? -x : x;
  }
};

// ---- exact oracle ----------------------------------------------------------

mpq_class Q(double x) { return mpq_class(x); }
int sgn_q(const mpq_class& q) { return sgn(q.get_num()); }

// Determinant by cofactor expansion along the first row (n <= 5).
mpq_class det_q(const std::vector<std::vector<mpq_class>>& m) {
  const size_t n = m.size();
  if (n == 1) return m[0][0];
  if (n == 2) return m[0][0] * m[1][1] - m[0][1] * m[1][0];
  mpq_class d = 0;
  for (size_t j = 0; j < n; ++j) {
    if (sgn_q(m[0][j]) == 0) continue;
    std::vector<std::vector<mpq_class>> sub(n - 1);
    for (size_t i = 1; i < n; ++i)
      for (size_t k = 0; k < n; ++k)
        if (k != j) sub[i - 1].push_back(m[i][k]);
    const mpq_class t = m[0][j] * det_q(sub);
    if (j % 2 == 0)
      d += t;
    else
      d -= t;
  }
  return d;
}

int orient3d_q(const P3& a, const P3& b, const P3& c, const P3& d) {
  std::vector<std::vector<mpq_class>> m(3);
  const P3* r[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) m[i].push_back(Q((*r[i])[k]) - Q(d[k]));
  return sgn_q(det_q(m));
}

mpq_class insphere_det_q(const P3& a, const P3& b, const P3& c, const P3& d, const P3& e) {
  std::vector<std::vector<mpq_class>> m(4);
  const P3* r[4] = {&a, &b, &c, &d};
  for (int i = 0; i < 4; ++i) {
    mpq_class lift = 0;
    for (int k = 0; k < 3; ++k) {
      const mpq_class t = Q((*r[i])[k]) - Q(e[k]);
      m[i].push_back(t);
      lift += t * t;
    }
    m[i].push_back(lift);
  }
  return det_q(m);
}
int insphere_q(const P3& a, const P3& b, const P3& c, const P3& d, const P3& e) {
  return sgn_q(insphere_det_q(a, b, c, d, e));
}

int orient2d_q(const double* a, const double* b, const double* c) {
  return sgn_q((Q(a[0]) - Q(c[0])) * (Q(b[1]) - Q(c[1])) -
               (Q(a[1]) - Q(c[1])) * (Q(b[0]) - Q(c[0])));
}

int incircle_q(const double* a, const double* b, const double* c, const double* d) {
  std::vector<std::vector<mpq_class>> m(3);
  const double* r[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    const mpq_class x = Q(r[i][0]) - Q(d[0]), y = Q(r[i][1]) - Q(d[1]);
    m[i] = {x, y, x * x + y * y};
  }
  return sgn_q(det_q(m));
}

// In-circle of coplanar 3D points through the exact circumcenter:
// center = a + ((|u|^2 v - |v|^2 u) x (u x v)) / (2 |u x v|^2), u = b - a,
// v = c - a; > 0 when |d - center| < |a - center|.
int incircle_coplanar_q(const P3& a, const P3& b, const P3& c, const P3& d) {
  mpq_class u[3], v[3], n[3], w[3], ctr[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = Q(b[k]) - Q(a[k]);
    v[k] = Q(c[k]) - Q(a[k]);
  }
  auto cross = [](const mpq_class* x, const mpq_class* y, mpq_class* out) {
    out[0] = x[1] * y[2] - x[2] * y[1];
    out[1] = x[2] * y[0] - x[0] * y[2];
    out[2] = x[0] * y[1] - x[1] * y[0];
  };
  cross(u, v, n);
  const mpq_class uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const mpq_class vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  const mpq_class nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  mpq_class t[3];
  for (int k = 0; k < 3; ++k) t[k] = uu * v[k] - vv * u[k];
  cross(t, n, w);
  mpq_class r2 = 0, d2 = 0;
  for (int k = 0; k < 3; ++k) {
    ctr[k] = Q(a[k]) + w[k] / (2 * nn);
    r2 += (Q(a[k]) - ctr[k]) * (Q(a[k]) - ctr[k]);
    d2 += (Q(d[k]) - ctr[k]) * (Q(d[k]) - ctr[k]);
  }
  return sgn_q(r2 - d2);
}

// ---- helpers ---------------------------------------------------------------

std::string hex(const P3& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%a, %a, %a)", p[0], p[1], p[2]);
  return buf;
}
template <size_t N>
std::string describe(const std::array<P3, N>& pts) {
  std::string s;
  for (const P3& p : pts) s += hex(p) + " ";
  return s;
}

#define SIGN_CHECK(got, want, what) \
  do {                              \
    const int got_ = (got);         \
    const int want_ = (want);       \
    if (got_ != want_) {            \
      INFO(what);                   \
      CHECK(got_ == want_);         \
    } else {                        \
      CHECK(got_ == want_);         \
    }                               \
  } while (0)

// Moves x by `ulps` ulps; zero stays zero (one ulp of 0 is a subnormal, out
// of the supported range).
double bump(double x, int ulps) {
  if (x == 0.0) return x;
  for (; ulps > 0; --ulps) x = std::nextafter(x, HUGE_VAL);
  for (; ulps < 0; ++ulps) x = std::nextafter(x, -HUGE_VAL);
  return x;
}

// Moves one random coordinate of p by -2..2 ulps (half of the time).
void maybe_bump(Rng& r, P3& p) {
  if (r.next() & 1) p[r.range(0, 2)] = bump(p[r.range(0, 2)], r.range(-2, 2));
}

int parity(const int* perm, int n) {
  int s = 1;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (perm[i] > perm[j]) s = -s;
  return s;
}

// Lattice points on spheres / circles centred at the origin.
std::vector<P3> sphere_points(int r2) {
  std::vector<P3> out;
  const int r = static_cast<int>(std::sqrt(static_cast<double>(r2))) + 1;
  for (int x = -r; x <= r; ++x)
    for (int y = -r; y <= r; ++y)
      for (int z = -r; z <= r; ++z)
        if (x * x + y * y + z * z == r2) out.push_back({double(x), double(y), double(z)});
  return out;
}

// Affine map of integer configurations: p -> base + p * 2^k (exact as long as
// the result is representable, which the callers ensure).
P3 place(const P3& p, const P3& base, int k) {
  return {base[0] + std::ldexp(p[0], k), base[1] + std::ldexp(p[1], k),
          base[2] + std::ldexp(p[2], k)};
}

// Scales used for the integer configurations: (base, exponent k), chosen so
// that every coordinate is 0 or within [1e-50, 1e50].
struct Frame {
  P3 base;
  int k;
};
Frame random_frame(Rng& r) {
  switch (r.range(0, 5)) {
    case 0:  // small integers
      return {{0, 0, 0}, 0};
    case 1:  // powers of two around 1
      return {{0, 0, 0}, r.range(-30, 30)};
    case 2:  // near 1e50: integers up to ~2^10 times 2^155
      return {{0, 0, 0}, 155};
    case 3:  // tiny offsets of a point at ~2e-50: coordinates base + m ulps
      return {{0x1p-165, 0x1.8p-165, 0x1.4p-165}, -217};
    case 4:  // large base, offsets of a few ulps (2^113 at 2^165)
      return {{0x1p165, -0x1.8p165, 0x1.4p165}, 113};
    default:  // mixed: offsets of 2^-20 around a point at 1e3
      return {{1000.0, -1000.0, 0.0}, -20};
  }
}

// Random point whose coordinates mix all scales of the supported range.
double mixed_coordinate(Rng& r) {
  switch (r.range(0, 4)) {
    case 0:
      return 0.0;
    case 1:
      return r.at_exponent(r.range(-166, -160));  // >= 2^-166 > 1e-50
    case 2:
      return r.at_exponent(r.range(150, 165));  // < 2^166 < 1e50
    case 3:
      return r.at_exponent(r.range(-40, 40));
    default:
      return r.sym();
  }
}

// ---- 3D case generators (each fills pts) ------------------------------------

enum class Kind { Uniform, Exponents, NearPlane, NearSphere, IntPlane, IntSphere, Mixed, Count };

const std::vector<P3>& lattice_sphere() {
  static const std::vector<P3> pts = sphere_points(3 * 3 * 5 * 5 * 2);  // r^2 = 450
  return pts;
}

template <size_t N>
void generate(Rng& r, Kind kind, std::array<P3, N>& pts) {
  switch (kind) {
    case Kind::Uniform:
      for (P3& p : pts) p = {r.sym(), r.sym(), r.sym()};
      break;
    case Kind::Exponents: {
      const int e = r.range(-160, 160);
      for (P3& p : pts)
        for (double& x : p) x = r.at_exponent(e + r.range(-4, 0));
      break;
    }
    case Kind::NearPlane: {  // last point rounded onto the plane of the first three
      const double s = std::ldexp(1.0, r.range(-30, 30));
      for (P3& p : pts) p = {s * r.sym(), s * r.sym(), s * r.sym()};
      for (size_t i = 3; i < N; ++i) {
        const double u = r.sym(), v = r.sym();
        for (int k = 0; k < 3; ++k)
          pts[i][k] = pts[0][k] + u * (pts[1][k] - pts[0][k]) + v * (pts[2][k] - pts[0][k]);
        maybe_bump(r, pts[i]);
      }
      break;
    }
    case Kind::NearSphere: {  // rounded points of a sphere
      const double s = std::ldexp(1.0, r.range(-30, 30));
      const P3 c = {s * r.sym(), s * r.sym(), s * r.sym()};
      const double rad = s * (0.1 + r.unit());
      for (P3& p : pts) {
        P3 v = {r.sym(), r.sym(), r.sym()};
        const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + 1e-300;
        for (int k = 0; k < 3; ++k) p[k] = c[k] + rad * v[k] / len;
        maybe_bump(r, p);
      }
      break;
    }
    case Kind::IntPlane: {  // z = alpha x + beta y + gamma, exactly
      const Frame f = random_frame(r);
      const int al = r.range(-3, 3), be = r.range(-3, 3), ga = r.range(-10, 10);
      const int ax = r.range(0, 2);
      for (P3& p : pts) {
        const int x = r.range(-20, 20), y = r.range(-20, 20);
        P3 q;
        q[ax] = al * x + be * y + ga;
        q[(ax + 1) % 3] = x;
        q[(ax + 2) % 3] = y;
        p = place(q, f.base, f.k);
        if (r.range(0, 3) == 0) maybe_bump(r, p);
      }
      break;
    }
    case Kind::IntSphere: {  // lattice points of a sphere, translated
      const Frame f = random_frame(r);
      const auto& s = lattice_sphere();
      const P3 t = {double(r.range(-5, 5)), double(r.range(-5, 5)), double(r.range(-5, 5))};
      for (P3& p : pts) {
        const P3& q = s[r.next() % s.size()];
        p = place({q[0] + t[0], q[1] + t[1], q[2] + t[2]}, f.base, f.k);
        if (r.range(0, 3) == 0) maybe_bump(r, p);
      }
      break;
    }
    default:
      for (P3& p : pts)
        for (double& x : p) x = mixed_coordinate(r);
      break;
  }
}

const char* kind_name(Kind k) {
  static const char* names[] = {"uniform",   "exponents",  "near-plane", "near-sphere",
                                "int-plane", "int-sphere", "mixed"};
  return names[static_cast<int>(k)];
}

}  // namespace

// ---------------------------------------------------------------------------

TEST_CASE("orient3d matches the exact oracle", "[predicates]") {
  Rng r(11);
  int zeros = 0;
  for (int kind = 0; kind < static_cast<int>(Kind::Count); ++kind) {
    for (int it = 0; it < 6000; ++it) {
      std::array<P3, 4> p;
      generate(r, static_cast<Kind>(kind), p);
      const int want = orient3d_q(p[0], p[1], p[2], p[3]);
      zeros += want == 0;
      SIGN_CHECK(pred::orient3d(p[0].data(), p[1].data(), p[2].data(), p[3].data()), want,
                 std::string(kind_name(static_cast<Kind>(kind))) + " " + describe(p));
    }
  }
  CHECK(zeros > 3000);  // the degenerate generators really are degenerate
}

TEST_CASE("insphere matches the exact oracle", "[predicates]") {
  Rng r(12);
  int zeros = 0;
  for (int kind = 0; kind < static_cast<int>(Kind::Count); ++kind) {
    for (int it = 0; it < 6000; ++it) {
      std::array<P3, 5> p;
      generate(r, static_cast<Kind>(kind), p);
      const int want = insphere_q(p[0], p[1], p[2], p[3], p[4]);
      zeros += want == 0;
      SIGN_CHECK(pred::insphere(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data()),
                 want, std::string(kind_name(static_cast<Kind>(kind))) + " " + describe(p));
    }
  }
  CHECK(zeros > 3000);
}

// orient3d of the first four points and insphere of all five against the
// oracle; returns the oracle's insphere sign.
int check_orient3d_insphere(const std::array<P3, 5>& p) {
  SIGN_CHECK(pred::orient3d(p[0].data(), p[1].data(), p[2].data(), p[3].data()),
             orient3d_q(p[0], p[1], p[2], p[3]), describe(p));
  const int w4 = insphere_q(p[0], p[1], p[2], p[3], p[4]);
  SIGN_CHECK(pred::insphere(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data()), w4,
             describe(p));
  return w4;
}

TEST_CASE("small integer coordinates take the exact double evaluation and match the oracle",
          "[predicates]") {
  // Integer points up to the limits of the fast path (|differences| summing
  // to 2^9 for insphere, 2^16 for orient3d) and just beyond, many of them
  // exactly coplanar or co-spherical (a small grid).
  Rng r(13);
  int zeros = 0;
  for (int it = 0; it < 20000; ++it) {
    const double span = it % 3 == 0 ? 4 : it % 3 == 1 ? 64 : 20000;
    std::array<P3, 5> p;
    for (auto& q : p)
      for (double& x : q) x = std::floor(span * r.unit()) - std::floor(span / 2);
    zeros += check_orient3d_insphere(p) == 0;
  }
  CHECK(zeros > 1000);
}

TEST_CASE("points in an axis-parallel plane or on an axis-parallel line give exact zeros",
          "[predicates]") {
  // CAD models: most exact zeros are points sharing one coordinate (not
  // integers). The predicates answer 0 for a zero column of differences
  // before the exact stage; compare with the oracle, with points that share
  // a coordinate only nearly (one ulp apart) mixed in.
  Rng r(17);
  int zeros = 0;
  for (int it = 0; it < 20000; ++it) {
    const int axis = it % 3;
    const double level = 1000 * r.sym();
    std::array<P3, 5> p;
    for (auto& q : p) {
      for (double& x : q) x = 1000 * r.sym();
      q[axis] = level;
      if (it % 7 == 0 && &q == &p[4]) q[axis] = std::nextafter(level, 1e300);
    }
    zeros += check_orient3d_insphere(p) == 0;
    // 2D: the xy projection; three or four points on the line x = level or
    // y = level (axis 0 or 1), the fourth nearly on it now and then.
    if (axis < 2) {
      const double* q[4] = {p[0].data(), p[1].data(), p[2].data(), p[4].data()};
      SIGN_CHECK(pred::orient2d(q[0], q[1], q[2]), orient2d_q(q[0], q[1], q[2]), describe(p));
      SIGN_CHECK(pred::incircle(q[0], q[1], q[2], q[3]), incircle_q(q[0], q[1], q[2], q[3]),
                 describe(p));
    }
  }
  CHECK(zeros > 15000);
}

TEST_CASE("insphere is exact on nearly cospherical points at the range limits", "[predicates]") {
  // Lattice points of a sphere placed at tiny (2^-217 offsets of a point near
  // 2e-50: degree-5 products near 2^-1085, below the smallest subnormal
  // unless the exact stage rescales) and huge scales, then moved by an ulp.
  Rng r(13);
  const uint64_t out_of_range = pred::counters().out_of_range;
  const auto& s = lattice_sphere();
  const Frame frames[3] = {{{0x1p-165, 0x1.8p-165, 0x1.4p-165}, -217},
                           {{0x1p165, -0x1.8p165, 0x1.4p165}, 113},
                           {{0, 0, 0}, 155}};
  for (int it = 0; it < 6000; ++it) {
    const Frame& f = frames[it % 3];
    std::array<P3, 5> p;
    for (P3& q : p) q = place(s[r.next() % s.size()], f.base, f.k);
    if (it % 2) p[4][r.range(0, 2)] = bump(p[4][r.range(0, 2)], r.range(0, 1) ? 1 : -1);
    const int want = insphere_q(p[0], p[1], p[2], p[3], p[4]);
    SIGN_CHECK(pred::insphere(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data()),
               want, describe(p));
    SIGN_CHECK(pred::orient3d(p[0].data(), p[1].data(), p[2].data(), p[4].data()),
               orient3d_q(p[0], p[1], p[2], p[4]), describe(p));
  }
  // A configuration whose determinant is a single 2^-1085: only exact with
  // the rescaling (it would underflow to 0 otherwise).
  const double u = 0x1p-217, b = 0x1p-165;
  const P3 a{b + u, b, b}, c{b, b + u, b}, d{b, b, b + u}, e{b, b, b}, q{b + u, b + u, b + u};
  CHECK(orient3d_q(a, c, d, e) != 0);
  CHECK(pred::insphere(a.data(), c.data(), d.data(), e.data(), q.data()) ==
        insphere_q(a, c, d, e, q));
  CHECK(pred::counters().out_of_range == out_of_range);
}

TEST_CASE("orient3d and insphere flip sign with odd permutations", "[predicates]") {
  Rng r(14);
  int perm[5] = {0, 1, 2, 3, 4};
  for (int it = 0; it < 1500; ++it) {
    std::array<P3, 5> p;
    generate(r, static_cast<Kind>(it % static_cast<int>(Kind::Count)), p);
    const int o = pred::orient3d(p[0].data(), p[1].data(), p[2].data(), p[3].data());
    const int s = pred::insphere(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data());
    SIGN_CHECK(s, insphere_q(p[0], p[1], p[2], p[3], p[4]), describe(p));
    for (int i = 0; i < 5; ++i) perm[i] = i;
    // All 120 permutations of the five insphere rows. Inputs that reach the
    // raw exact form are answered from its memo after the first call, which
    // must apply the permutation's parity.
    do {
      const int par = parity(perm, 5);
      SIGN_CHECK(pred::insphere(p[perm[0]].data(), p[perm[1]].data(), p[perm[2]].data(),
                                p[perm[3]].data(), p[perm[4]].data()),
                 par * s, describe(p));
      if (perm[4] == 4)
        SIGN_CHECK(pred::orient3d(p[perm[0]].data(), p[perm[1]].data(), p[perm[2]].data(),
                                  p[perm[3]].data()),
                   par * o, describe(p));
    } while (std::next_permutation(perm, perm + 5));
  }
}

TEST_CASE("orient2d, incircle and orient2d_projected match the exact oracle", "[predicates]") {
  Rng r(15);
  std::vector<std::array<double, 2>> circle;  // lattice points of x^2 + y^2 = 5^6
  for (int x = -125; x <= 125; ++x)
    for (int y = -125; y <= 125; ++y)
      if (x * x + y * y == 15625) circle.push_back({double(x), double(y)});
  REQUIRE(circle.size() >= 16);
  int zeros_o = 0, zeros_c = 0;
  for (int it = 0; it < 42000; ++it) {
    double p[4][2];
    switch (it % 7) {
      case 0:
        for (auto& q : p) q[0] = r.sym(), q[1] = r.sym();
        break;
      case 1: {
        const int e = r.range(-160, 160);
        for (auto& q : p) q[0] = r.at_exponent(e - r.range(0, 3)), q[1] = r.at_exponent(e);
        break;
      }
      case 2: {  // near a line (rounded), then bumped
        for (int i = 0; i < 2; ++i) p[i][0] = r.sym(), p[i][1] = r.sym();
        for (int i = 2; i < 4; ++i) {
          const double t = 4 * r.sym();
          for (int k = 0; k < 2; ++k) p[i][k] = p[0][k] + t * (p[1][k] - p[0][k]);
          if (r.next() & 1) p[i][r.range(0, 1)] = bump(p[i][r.range(0, 1)], r.range(-2, 2));
        }
        break;
      }
      case 3: {  // near a circle (rounded), then bumped
        const double cx = r.sym(), cy = r.sym(), rad = 0.1 + r.unit();
        for (auto& q : p) {
          const double t = 6.283185307179586 * r.unit();
          q[0] = cx + rad * std::cos(t);
          q[1] = cy + rad * std::sin(t);
          if (r.next() & 1) q[r.range(0, 1)] = bump(q[r.range(0, 1)], r.range(-2, 2));
        }
        break;
      }
      case 4: {  // exactly collinear integers, scaled
        const Frame f = random_frame(r);
        const int dx = r.range(-5, 5), dy = r.range(-5, 5), ox = r.range(-9, 9),
                  oy = r.range(-9, 9);
        for (auto& q : p) {
          const int t = r.range(-10, 10);
          const P3 g = place({double(ox + t * dx), double(oy + t * dy), 0.0}, f.base, f.k);
          q[0] = g[0], q[1] = g[1];
        }
        break;
      }
      case 5: {  // exactly cocircular lattice points, scaled
        const Frame f = random_frame(r);
        for (auto& q : p) {
          const auto& c = circle[r.next() % circle.size()];
          const P3 g = place({c[0] + 3, c[1] - 2, 0.0}, f.base, f.k);
          q[0] = g[0], q[1] = g[1];
          if (r.range(0, 3) == 0) q[r.range(0, 1)] = bump(q[r.range(0, 1)], r.range(-1, 1));
        }
        break;
      }
      default:
        for (auto& q : p) q[0] = mixed_coordinate(r), q[1] = mixed_coordinate(r);
        break;
    }
    const int wo = orient2d_q(p[0], p[1], p[2]);
    const int wc = incircle_q(p[0], p[1], p[2], p[3]);
    zeros_o += wo == 0;
    zeros_c += wc == 0;
    char buf[256];
    std::snprintf(buf, sizeof buf, "case %d: (%a,%a) (%a,%a) (%a,%a) (%a,%a)", it % 7, p[0][0],
                  p[0][1], p[1][0], p[1][1], p[2][0], p[2][1], p[3][0], p[3][1]);
    SIGN_CHECK(pred::orient2d(p[0], p[1], p[2]), wo, buf);
    SIGN_CHECK(pred::orient2d(p[1], p[0], p[2]), -wo, buf);
    SIGN_CHECK(pred::incircle(p[0], p[1], p[2], p[3]), wc, buf);
    SIGN_CHECK(pred::incircle(p[3], p[1], p[2], p[0]), -wc, buf);
    SIGN_CHECK(pred::incircle(p[1], p[2], p[0], p[3]), wc, buf);
    // Embedded in 3D with the third coordinate on each axis in turn.
    const double z = r.sym();
    for (int drop = 0; drop < 3; ++drop) {
      double a[3], b[3], c[3];
      const int i = (drop + 1) % 3, j = (drop + 2) % 3;
      a[drop] = z, b[drop] = -z, c[drop] = 2 * z;
      a[i] = p[0][0], a[j] = p[0][1];
      b[i] = p[1][0], b[j] = p[1][1];
      c[i] = p[2][0], c[j] = p[2][1];
      SIGN_CHECK(pred::orient2d_projected(a, b, c, drop), wo, buf);
    }
  }
  CHECK(zeros_o > 3000);
  CHECK(zeros_c > 1500);
}

TEST_CASE("collinear3d matches the exact oracle", "[predicates]") {
  Rng r(16);
  for (int it = 0; it < 10000; ++it) {
    P3 a, b, c;
    const Frame f = random_frame(r);
    const P3 o = {double(r.range(-9, 9)), double(r.range(-9, 9)), double(r.range(-9, 9))};
    const P3 d = {double(r.range(-4, 4)), double(r.range(-4, 4)), double(r.range(-4, 4))};
    auto on_line = [&](int t) {
      return place({o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}, f.base, f.k);
    };
    a = on_line(r.range(-9, 9));
    b = on_line(r.range(-9, 9));
    c = on_line(r.range(-9, 9));
    if (it % 2) c[r.range(0, 2)] = bump(c[r.range(0, 2)], r.range(-1, 1));
    if (it % 5 == 0) a = {mixed_coordinate(r), mixed_coordinate(r), mixed_coordinate(r)};
    bool want = true;
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const mpq_class cr =
          (Q(b[i]) - Q(a[i])) * (Q(c[j]) - Q(a[j])) - (Q(b[j]) - Q(a[j])) * (Q(c[i]) - Q(a[i]));
      if (sgn_q(cr) != 0) want = false;
    }
    CHECK(pred::collinear3d(a.data(), b.data(), c.data()) == want);
  }
}

TEST_CASE("orient2d_centroid_projected matches the exact oracle, centroids on the line included",
          "[predicates]") {
  Rng r(19);
  for (int it = 0; it < 20000; ++it) {
    const Frame f = random_frame(r);
    // Lattice points; every third case puts the centroid on the line ab
    // (c2 = 3m - c0 - c1 for a lattice point m on it).
    auto lattice = [&] { return P3{double(r.range(-9, 9)), double(r.range(-9, 9)), double(r.range(-9, 9))}; };
    const P3 a0 = lattice(), d = lattice(), c0 = lattice(), c1 = lattice();
    P3 c2 = lattice();
    if (it % 3 == 0) {
      const int t = r.range(-3, 3);
      for (int k = 0; k < 3; ++k) c2[k] = 3 * (a0[k] + t * d[k]) - c0[k] - c1[k];
    }
    const P3 b0 = {a0[0] + d[0], a0[1] + d[1], a0[2] + d[2]};
    P3 a = place(a0, f.base, f.k), b = place(b0, f.base, f.k);
    P3 c[3] = {place(c0, f.base, f.k), place(c1, f.base, f.k), place(c2, f.base, f.k)};
    if (it % 2) maybe_bump(r, c[r.range(0, 2)]);
    if (it % 7 == 0) c[0] = {mixed_coordinate(r), mixed_coordinate(r), mixed_coordinate(r)};
    const int drop = r.range(0, 2);
    const int i = (drop + 1) % 3, j = (drop + 2) % 3;
    mpq_class sum = 0;
    for (const P3& x : c)
      sum += (Q(b[i]) - Q(a[i])) * (Q(x[j]) - Q(a[j])) - (Q(b[j]) - Q(a[j])) * (Q(x[i]) - Q(a[i]));
    const double* cs[3] = {c[0].data(), c[1].data(), c[2].data()};
    INFO(hex(a) << " " << hex(b) << " " << hex(c[0]) << " " << hex(c[1]) << " " << hex(c[2]));
    CHECK(pred::orient2d_centroid_projected(a.data(), b.data(), cs, drop) == sgn_q(sum));
  }
}

TEST_CASE("orient3d_centroid matches the exact oracle, centroids on the plane included",
          "[predicates]") {
  Rng r(23);
  for (int it = 0; it < 20000; ++it) {
    const Frame f = random_frame(r);
    // Lattice points; every third case puts the centroid on the plane abc
    // (p2 = 3m - p0 - p1 for a lattice point m of it).
    auto lattice = [&] { return P3{double(r.range(-9, 9)), double(r.range(-9, 9)), double(r.range(-9, 9))}; };
    const P3 a0 = lattice(), b0 = lattice(), c0 = lattice(), p0 = lattice(), p1 = lattice();
    P3 p2 = lattice();
    if (it % 3 == 0) {
      const int s = r.range(-2, 2), t = r.range(-2, 2);
      for (int k = 0; k < 3; ++k)
        p2[k] = 3 * (a0[k] + s * (b0[k] - a0[k]) + t * (c0[k] - a0[k])) - p0[k] - p1[k];
    }
    const P3 a = place(a0, f.base, f.k), b = place(b0, f.base, f.k), c = place(c0, f.base, f.k);
    P3 p[3] = {place(p0, f.base, f.k), place(p1, f.base, f.k), place(p2, f.base, f.k)};
    if (it % 2) maybe_bump(r, p[r.range(0, 2)]);
    if (it % 7 == 0) p[0] = {mixed_coordinate(r), mixed_coordinate(r), mixed_coordinate(r)};
    mpq_class m[3];
    for (int k = 0; k < 3; ++k) m[k] = (Q(p[0][k]) + Q(p[1][k]) + Q(p[2][k])) / 3;
    mpq_class row[3][3];
    const P3* abc[3] = {&a, &b, &c};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) row[i][k] = Q((*abc[i])[k]) - m[k];
    const mpq_class det = row[0][0] * (row[1][1] * row[2][2] - row[1][2] * row[2][1]) -
                          row[0][1] * (row[1][0] * row[2][2] - row[1][2] * row[2][0]) +
                          row[0][2] * (row[1][0] * row[2][1] - row[1][1] * row[2][0]);
    const double* ps[3] = {p[0].data(), p[1].data(), p[2].data()};
    INFO(hex(a) << " " << hex(b) << " " << hex(c) << " " << hex(p[0]) << " " << hex(p[1]) << " " << hex(p[2]));
    CHECK(pred::orient3d_centroid(a.data(), b.data(), c.data(), ps) == sgn_q(det));
  }
}

TEST_CASE("dot_sign matches the exact oracle, right angles included", "[predicates]") {
  Rng r(17);
  for (int it = 0; it < 20000; ++it) {
    const Frame f = random_frame(r);
    // v and two lattice directions; every third case makes them orthogonal.
    const P3 o = {double(r.range(-9, 9)), double(r.range(-9, 9)), double(r.range(-9, 9))};
    const P3 u = {double(r.range(-5, 5)), double(r.range(-5, 5)), double(r.range(-5, 5))};
    P3 w = {double(r.range(-5, 5)), double(r.range(-5, 5)), double(r.range(-5, 5))};
    // Every third case a right angle: w = u x (1, 2, 3) is orthogonal to u.
    if (it % 3 == 0) w = {2 * u[2] - 3 * u[1], 3 * u[0] - u[2], u[1] - 2 * u[0]};
    P3 v = place(o, f.base, f.k);
    P3 a = place({o[0] + u[0], o[1] + u[1], o[2] + u[2]}, f.base, f.k);
    P3 b = place({o[0] + w[0], o[1] + w[1], o[2] + w[2]}, f.base, f.k);
    if (it % 2) maybe_bump(r, a);
    if (it % 7 == 0) v = {mixed_coordinate(r), mixed_coordinate(r), mixed_coordinate(r)};
    mpq_class dot = 0;
    for (int k = 0; k < 3; ++k) dot += (Q(a[k]) - Q(v[k])) * (Q(b[k]) - Q(v[k]));
    INFO(hex(a) << " " << hex(v) << " " << hex(b));
    CHECK(pred::dot_sign(a.data(), v.data(), b.data()) == sgn_q(dot));
    // The four-point form, (a - v) . (b - w), against the same oracle.
    P3 w4 = place({o[0] - w[1], o[1] + u[0], o[2]}, f.base, f.k);
    if (it % 5 == 0) w4 = {mixed_coordinate(r), mixed_coordinate(r), mixed_coordinate(r)};
    mpq_class dot4 = 0;
    for (int k = 0; k < 3; ++k) dot4 += (Q(a[k]) - Q(v[k])) * (Q(b[k]) - Q(w4[k]));
    CHECK(pred::dot_sign(a.data(), v.data(), b.data(), w4.data()) == sgn_q(dot4));
  }
}

TEST_CASE("dot_sign orders points one ulp apart along a line", "[predicates]") {
  // The validator orders a segment's points by (x - y) . (b - a): in doubles
  // both projections below round to the same value and the order was lost.
  const double a[3] = {0, 0, 0}, b[3] = {1, 1e20, -1e20};
  const double x[3] = {5, 5, 5}, y[3] = {std::nextafter(5.0, 6.0), 5, 5};
  auto along = [&](const double* p) { return p[0] * b[0] + p[1] * b[1] + p[2] * b[2]; };
  CHECK(along(x) == along(y));
  CHECK(pred::dot_sign(x, y, b, a) < 0);
  CHECK(pred::dot_sign(y, x, b, a) > 0);
  CHECK(pred::dot_sign(x, x, b, a) == 0);
}

namespace {

// Integer rotation (times |q|^2) from a quaternion with integer components:
// maps circles to circles, so cocircular lattice points stay cocircular.
P3 rotate(const int* q, const P3& p) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double m[3][3] = {
      {w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)},
      {2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)},
      {2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z}};
  return {m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2],
          m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2],
          m[2][0] * p[0] + m[2][1] * p[1] + m[2][2] * p[2]};
}

// Four coplanar points in a tilted plane: cocircular lattice points (or
// points inside/outside the circle) rotated by an integer quaternion, scaled.
std::array<P3, 4> coplanar_quad(Rng& r, bool cocircular) {
  static std::vector<P3> circle;
  if (circle.empty())
    for (int x = -25; x <= 25; ++x)
      for (int y = -25; y <= 25; ++y)
        if (x * x + y * y == 625) circle.push_back({double(x), double(y), 0.0});
  const int q[4] = {r.range(-3, 3), r.range(-3, 3), r.range(-3, 3), r.range(1, 3)};
  const Frame f = random_frame(r);
  const double sh[2] = {double(r.range(-4, 4)), double(r.range(-4, 4))};
  std::array<P3, 4> out;
  for (int i = 0; i < 4; ++i) {
    P3 c = circle[r.next() % circle.size()];
    if (!cocircular && i == 3) c = {double(r.range(-30, 30)), double(r.range(-30, 30)), 0.0};
    c[0] += sh[0];
    c[1] += sh[1];
    out[i] = place(rotate(q, c), f.base, f.k);
  }
  return out;
}

// incircle_coplanar of p and of p with its first two points swapped (the
// answer does not depend on the orientation) against the oracle; returns
// the oracle's sign.
int check_incircle_coplanar(const std::array<P3, 4>& p) {
  const int want = incircle_coplanar_q(p[0], p[1], p[2], p[3]);
  SIGN_CHECK(pred::incircle_coplanar(p[0].data(), p[1].data(), p[2].data(), p[3].data()), want,
             describe(p));
  SIGN_CHECK(pred::incircle_coplanar(p[1].data(), p[0].data(), p[2].data(), p[3].data()), want,
             describe(p));
  return want;
}

}  // namespace

TEST_CASE("incircle_coplanar matches the exact circumcenter oracle", "[predicates]") {
  Rng r(17);
  int zeros = 0, tested = 0;
  for (int it = 0; it < 8000; ++it) {
    const std::array<P3, 4> p = coplanar_quad(r, it % 2 == 0);
    if (pred::collinear3d(p[0].data(), p[1].data(), p[2].data())) continue;
    REQUIRE(orient3d_q(p[0], p[1], p[2], p[3]) == 0);
    zeros += check_incircle_coplanar(p) == 0;
    ++tested;
  }
  CHECK(tested > 6000);
  CHECK(zeros > 1000);
}

TEST_CASE("incircle_coplanar in axis-parallel planes matches the oracle", "[predicates]") {
  // CAD hull faces: the four points share one coordinate exactly (the 2D
  // path). Rectangle corners are co-circular whatever the rounding of their
  // decimal coordinates; the fourth point is a corner, a corner moved by an
  // ulp, or a random decimal point.
  Rng r(29);
  int zeros = 0, tested = 0;
  for (int it = 0; it < 6000; ++it) {
    const int k = it % 3, i = k == 0 ? 1 : 0, j = k == 2 ? 1 : 2;
    const double level = r.range(-50, 50) * 0.127;
    const double u[2] = {r.range(-40, 40) * 0.1, r.range(-40, 40) * 0.1};
    const double v[2] = {r.range(-40, 40) * 0.3, r.range(-40, 40) * 0.3};
    std::array<P3, 4> rect;
    for (int c = 0; c < 4; ++c) {
      rect[c][k] = level;
      rect[c][i] = u[c & 1];
      rect[c][j] = v[(c >> 1) & 1];
    }
    std::array<P3, 4> p = {rect[0], rect[1], rect[3], rect[2]};
    std::swap(p[0], p[r.range(0, 2)]);
    if (it % 4 == 1) p[3][i] = bump(p[3][i], r.range(0, 1) ? 1 : -1);
    if (it % 4 == 2) p[3][i] = r.range(-60, 60) * 0.1, p[3][j] = r.range(-60, 60) * 0.3;
    if (pred::collinear3d(p[0].data(), p[1].data(), p[2].data())) continue;
    zeros += check_incircle_coplanar(p) == 0;
    ++tested;
  }
  CHECK(tested > 3000);
  CHECK(zeros > 1000);
}

namespace {

// Sign of the insphere determinant with every lift raised by eps^rank (rank 1
// for the largest id), evaluated exactly: the definition insphere_sos claims
// to simulate. Points must be integers (then every cofactor is an integer, and
// eps = 1 / (4 (1 + bound on the cofactors)) makes the lowest-order nonzero
// term dominate).
int insphere_perturbed_q(const std::array<P3, 5>& p, const std::array<uint32_t, 5>& ids) {
  double big = 1;
  for (const P3& q : p)
    for (double x : q) big = std::max(big, std::fabs(x));
  const mpq_class eps = mpq_class(1) / (4 * (1 + 24 * big * big * big));
  std::vector<std::vector<mpq_class>> m(5);
  for (int i = 0; i < 5; ++i) {
    int rank = 1;
    for (int j = 0; j < 5; ++j) rank += ids[j] > ids[i];
    mpq_class pert = 1;
    for (int k = 0; k < rank; ++k) pert *= eps;
    const mpq_class x = Q(p[i][0]), y = Q(p[i][1]), z = Q(p[i][2]);
    m[i] = {x, y, z, x * x + y * y + z * z + pert, mpq_class(1)};
  }
  return sgn_q(det_q(m));
}

std::array<uint32_t, 5> random_ids(Rng& r) {
  std::array<uint32_t, 5> ids;
  for (int i = 0; i < 5; ++i) {
    bool fresh;
    do {
      ids[i] = static_cast<uint32_t>(r.range(0, 40)) * 100000u + (r.next() & 1) * 0xfff00000u;
      fresh = true;
      for (int j = 0; j < i; ++j) fresh = fresh && ids[j] != ids[i];
    } while (!fresh);
  }
  return ids;
}

int sos(const std::array<P3, 5>& p, const std::array<uint32_t, 5>& id, const int* k) {
  return pred::insphere_sos(p[k[0]].data(), p[k[1]].data(), p[k[2]].data(), p[k[3]].data(),
                            p[k[4]].data(), id[k[0]], id[k[1]], id[k[2]], id[k[3]], id[k[4]]);
}

}  // namespace

TEST_CASE("insphere_sos equals the explicitly perturbed determinant", "[predicates][sos]") {
  Rng r(18);
  const auto& s = lattice_sphere();
  const std::vector<P3> small = sphere_points(9);  // many coplanar 4-subsets
  int ties = 0;
  for (int it = 0; it < 12000; ++it) {
    std::array<P3, 5> p;
    const std::vector<P3>& src = it % 3 == 0 ? small : s;
    for (P3& q : p) q = src[r.next() % src.size()];
    if (it % 4 == 1)
      p[4] = {double(r.range(-25, 25)), double(r.range(-25, 25)), double(r.range(-25, 25))};
    if (it % 4 == 2) p[4] = p[r.range(0, 3)];  // duplicate of a vertex
    const std::array<uint32_t, 5> ids = random_ids(r);
    bool distinct = true;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) distinct = distinct && p[i] != p[j];
    if (!distinct) continue;
    const int want = insphere_perturbed_q(p, ids);
    ties += insphere_q(p[0], p[1], p[2], p[3], p[4]) == 0;
    const int k[5] = {0, 1, 2, 3, 4};
    SIGN_CHECK(sos(p, ids, k), want, describe(p));
    // The tie entry (the caller already has the exact zero) decides alone.
    if (insphere_q(p[0], p[1], p[2], p[3], p[4]) == 0)
      SIGN_CHECK(pred::insphere_tie(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                    p[4].data(), ids[0], ids[1], ids[2], ids[3], ids[4]),
                 want, describe(p));
    if (orient3d_q(p[0], p[1], p[2], p[3]) != 0) CHECK(want != 0);
    // Permuting points together with their ids permutes the perturbed rows.
    int perm[5] = {0, 1, 2, 3, 4};
    for (int t = 0; t < 6; ++t) {
      for (int i = 4; i > 0; --i) std::swap(perm[i], perm[r.range(0, i)]);
      SIGN_CHECK(sos(p, ids, perm), parity(perm, 5) * want, describe(p));
    }
  }
  CHECK(ties > 5000);
}

TEST_CASE("insphere_sos picks exactly one triangulation of five cospherical points",
          "[predicates][sos]") {
  // Five cospherical points in convex position, no four coplanar, have two
  // tetrahedralizations: 2 tets sharing the triangle cde, or 3 tets around
  // the edge ab (ab crosses cde). With a consistent perturbation, exactly one
  // of them has every interior face locally Delaunay, and each face gets the
  // same answer from both of its tets.
  Rng r(19);
  const auto& s = lattice_sphere();
  int configs = 0, two = 0, three = 0;
  while (configs < 300) {
    std::array<P3, 5> p;
    for (P3& q : p) q = s[r.next() % s.size()];
    bool ok = true;
    int idx[5] = {0, 1, 2, 3, 4};
    for (int i = 0; i < 5 && ok; ++i)
      for (int j = i + 1; j < 5 && ok; ++j)
        for (int k = j + 1; k < 5 && ok; ++k)
          for (int l = k + 1; l < 5 && ok; ++l) ok = orient3d_q(p[i], p[j], p[k], p[l]) != 0;
    if (!ok) continue;
    // Find the pair (a, b) whose segment crosses the triangle of the others.
    bool found = false;
    for (int i = 0; i < 5 && !found; ++i)
      for (int j = i + 1; j < 5 && !found; ++j) {
        int o[3], n = 0;
        for (int k = 0; k < 5; ++k)
          if (k != i && k != j) o[n++] = k;
        const int s1 = orient3d_q(p[i], p[j], p[o[0]], p[o[1]]);
        const int s2 = orient3d_q(p[i], p[j], p[o[1]], p[o[2]]);
        const int s3 = orient3d_q(p[i], p[j], p[o[2]], p[o[0]]);
        if (s1 == s2 && s2 == s3) {
          idx[0] = i, idx[1] = j, idx[2] = o[0], idx[3] = o[1], idx[4] = o[2];
          found = true;
        }
      }
    REQUIRE(found);
    ++configs;
    std::array<P3, 5> q;
    for (int i = 0; i < 5; ++i) q[i] = p[idx[i]];
    // Positively oriented tets as index quadruples into q.
    auto tet = [&](int a, int b, int c, int d) {
      std::array<int, 4> t = {a, b, c, d};
      if (orient3d_q(q[a], q[b], q[c], q[d]) < 0) std::swap(t[0], t[1]);
      return t;
    };
    std::array<uint32_t, 5> ids = {0, 1, 2, 3, 4};
    for (int t = 0; t < 24; ++t) {
      if (t > 0) ids = random_ids(r);
      auto in = [&](const std::array<int, 4>& t4, int e) {
        return pred::insphere_sos(q[t4[0]].data(), q[t4[1]].data(), q[t4[2]].data(),
                                  q[t4[3]].data(), q[e].data(), ids[t4[0]], ids[t4[1]], ids[t4[2]],
                                  ids[t4[3]], ids[e]);
      };
      // 2 tets: (a, c, d, e) and (b, c, d, e).
      const auto t1 = tet(0, 2, 3, 4), t2 = tet(1, 2, 3, 4);
      const int f2a = in(t1, 1), f2b = in(t2, 0);
      CHECK(f2a == f2b);
      const bool two_ok = f2a < 0;
      // 3 tets around ab: u1 = (a,b,c,d), u2 = (a,b,d,e), u3 = (a,b,e,c). Both
      // neighbours of each lie beyond faces whose far vertex is the same point
      // (e for u1, c for u2, d for u3), and each pair shares a face.
      const auto u1 = tet(0, 1, 2, 3), u2 = tet(0, 1, 3, 4), u3 = tet(0, 1, 4, 2);
      const int g1 = in(u1, 4), g2 = in(u2, 2), g3 = in(u3, 3);
      CHECK(g1 == g2);
      CHECK(g2 == g3);
      const bool three_ok = g1 < 0 && g2 < 0 && g3 < 0;
      CHECK(two_ok != three_ok);
      // The choice agrees with the explicitly perturbed determinant: the
      // two-tet side is Delaunay iff b is outside the sphere of t1.
      const std::array<P3, 5> pts = {q[t1[0]], q[t1[1]], q[t1[2]], q[t1[3]], q[1]};
      const std::array<uint32_t, 5> pid = {ids[t1[0]], ids[t1[1]], ids[t1[2]], ids[t1[3]], ids[1]};
      CHECK((insphere_perturbed_q(pts, pid) < 0) == two_ok);
      two += two_ok;
      three += three_ok;
    }
  }
  CHECK(two > 100);
  CHECK(three > 100);
}

TEST_CASE("incircle_coplanar_sos is the limit of insphere_sos", "[predicates][sos]") {
  Rng r(20);
  int ties = 0, checked = 0;
  for (int it = 0; it < 8000; ++it) {
    std::array<P3, 4> p = coplanar_quad(r, it % 4 != 3);
    const P3 &a = p[0], &b = p[1], &c = p[2];
    P3 e = p[3];
    if (pred::collinear3d(a.data(), b.data(), c.data())) continue;
    bool distinct = !(a == e || b == e || c == e);
    if (!distinct) continue;
    if (it % 8 == 5) e[r.range(0, 2)] = bump(e[r.range(0, 2)], r.range(0, 1) ? 1 : -1);
    const std::array<uint32_t, 5> ids = random_ids(r);
    const int got = pred::incircle_coplanar_sos(a.data(), b.data(), c.data(), e.data(), ids[0],
                                                ids[1], ids[2], ids[3]);
    const int off = orient3d_q(a, b, c, e);
    if (off != 0) {
      SIGN_CHECK(got, off, describe(p));
      continue;
    }
    ++checked;
    SIGN_CHECK(pred::incircle_coplanar_sos_on_plane(a.data(), b.data(), c.data(), e.data(), ids[0],
                                                    ids[1], ids[2], ids[3]),
               got, describe(p));
    const int circle = incircle_coplanar_q(a, b, c, e);
    ties += circle == 0;
    if (circle != 0) SIGN_CHECK(got, circle, describe(p));
    // Reference: insphere_sos(a, b, c, q, e) for a point q on the outer side
    // (orient3d(a, b, c, q) > 0) with an arbitrary id.
    P3 q = a;
    int side = 0;
    for (int k = 0; k < 3 && side == 0; ++k) {
      q = a;
      q[k] = a[k] + std::ldexp(1.0, r.range(-3, 3)) * (std::fabs(a[k]) + 1.0);
      side = orient3d_q(a, b, c, q);
    }
    REQUIRE(side != 0);
    const bool flip = side < 0;  // use the face (b, a, c) so that q is outside
    const P3 &fa = flip ? b : a, &fb = flip ? a : b;
    const uint32_t ia = flip ? ids[1] : ids[0], ib = flip ? ids[0] : ids[1];
    const int want_ref = pred::insphere_sos(fa.data(), fb.data(), c.data(), q.data(), e.data(), ia,
                                            ib, ids[2], ids[4], ids[3]);
    const int got_face = pred::incircle_coplanar_sos(fa.data(), fb.data(), c.data(), e.data(), ia,
                                                     ib, ids[2], ids[3]);
    SIGN_CHECK(got_face, want_ref, describe(p));
    CHECK(got_face != 0);
  }
  CHECK(checked > 4000);
  CHECK(ties > 1000);
}

TEST_CASE("filters decide random inputs, and out-of-range inputs are counted", "[predicates]") {
  Rng r(21);
  const pred::Counters before = pred::counters();
  std::vector<P3> pts(4096);
  for (P3& p : pts) p = {r.unit(), r.unit(), r.unit()};
  int sum = 0;
  for (size_t i = 0; i + 4 < pts.size(); ++i) {
    sum += pred::orient3d(pts[i].data(), pts[i + 1].data(), pts[i + 2].data(), pts[i + 3].data());
    sum += pred::insphere(pts[i].data(), pts[i + 1].data(), pts[i + 2].data(), pts[i + 3].data(),
                          pts[i + 4].data());
  }
  const pred::Counters after = pred::counters();
  CHECK(after.orient3d_calls - before.orient3d_calls == pts.size() - 4);
  CHECK(after.insphere_calls - before.insphere_calls == pts.size() - 4);
  CHECK(after.orient3d_exact - before.orient3d_exact <= 2);
  CHECK(after.insphere_exact - before.insphere_exact <= 2);
  (void)sum;
  // A subnormal coordinate next to coordinates of 1 cannot be rescaled into
  // the exact domain of insphere (span of 1075 bits > 404): counted.
  const P3 a{1, 0, 0}, b{0, 1, 0}, c{0, 0, 1}, d{0, 0, 0}, e{0x1p-1074, 0, 0};
  const uint64_t oor = pred::counters().out_of_range;
  pred::insphere(a.data(), b.data(), c.data(), d.data(), e.data());
  CHECK(pred::counters().out_of_range == oor + 1);
}

namespace {

double plain_orient3d(const double* a, const double* b, const double* c, const double* d) {
  const double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
  const double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
  const double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
  return adx * (bdy * cdz - bdz * cdy) + bdx * (cdy * adz - cdz * ady) +
         cdx * (ady * bdz - adz * bdy);
}

double plain_insphere(const double* a, const double* b, const double* c, const double* d,
                      const double* e) {
  const double aex = a[0] - e[0], aey = a[1] - e[1], aez = a[2] - e[2];
  const double bex = b[0] - e[0], bey = b[1] - e[1], bez = b[2] - e[2];
  const double cex = c[0] - e[0], cey = c[1] - e[1], cez = c[2] - e[2];
  const double dex = d[0] - e[0], dey = d[1] - e[1], dez = d[2] - e[2];
  const double ab = aex * bey - bex * aey, bc = bex * cey - cex * bey;
  const double cd = cex * dey - dex * cey, da = dex * aey - aex * dey;
  const double ac = aex * cey - cex * aey, bd = bex * dey - dex * bey;
  const double abc = aez * bc - bez * ac + cez * ab, bcd = bez * cd - cez * bd + dez * bc;
  const double cda = cez * da + dez * ac + aez * cd, dab = dez * ab + aez * bd + bez * da;
  const double la = aex * aex + aey * aey + aez * aez, lb = bex * bex + bey * bey + bez * bez;
  const double lc = cex * cex + cey * cey + cez * cez, ld = dex * dex + dey * dey + dez * dez;
  return (ld * abc - lc * dab) + (lb * cda - la * bcd);
}

// Thread CPU time, best of five runs (the machine may be busy).
double cpu_ns() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}
template <class F>
double ns_per_call(int calls, F&& f) {
  double best = 1e300;
  for (int rep = 0; rep < 5; ++rep) {
    const double t0 = cpu_ns();
    f();
    best = std::min(best, (cpu_ns() - t0) / calls);
  }
  return best;
}

}  // namespace

TEST_CASE("predicate micro benchmark (printed, not asserted)", "[predicates][bench]") {
  Rng r(22);
  const int n = 1 << 16, calls = 1000000;
  std::vector<double> xyz(3 * n);
  for (double& x : xyz) x = r.unit();
  std::vector<uint32_t> idx(calls + 8);
  for (uint32_t& i : idx) i = static_cast<uint32_t>(r.next() % n);
  auto pt = [&](int i) { return &xyz[3 * size_t(idx[i])]; };
  volatile long sink = 0;
  long acc = 0;
  const double t_plain_o = ns_per_call(calls, [&] {
    for (int i = 0; i < calls; ++i)
      acc += plain_orient3d(pt(i), pt(i + 1), pt(i + 2), pt(i + 3)) > 0;
  });
  const double t_o = ns_per_call(calls, [&] {
    for (int i = 0; i < calls; ++i) acc += pred::orient3d(pt(i), pt(i + 1), pt(i + 2), pt(i + 3));
  });
  const double t_plain_s = ns_per_call(calls, [&] {
    for (int i = 0; i < calls; ++i)
      acc += plain_insphere(pt(i), pt(i + 1), pt(i + 2), pt(i + 3), pt(i + 4)) > 0;
  });
  const double t_s = ns_per_call(calls, [&] {
    for (int i = 0; i < calls; ++i)
      acc += pred::insphere(pt(i), pt(i + 1), pt(i + 2), pt(i + 3), pt(i + 4));
  });
  // Exact stage alone, on exactly cospherical lattice points (filter fails).
  const auto& s = lattice_sphere();
  const int exact_calls = 5000;
  const double t_exact = ns_per_call(exact_calls, [&] {
    for (int i = 0; i < exact_calls; ++i)
      acc += pred::insphere(s[i % s.size()].data(), s[(i * 7 + 1) % s.size()].data(),
                            s[(i * 13 + 2) % s.size()].data(), s[(i * 17 + 3) % s.size()].data(),
                            s[(i * 29 + 5) % s.size()].data());
  });
  // Exact stage forced on random unit-cube doubles: coordinates within 125
  // bits of each other, so the integer form (two limbs for most sets).
  const double t_int53 = ns_per_call(exact_calls, [&] {
    for (int i = 0; i < exact_calls; ++i)
      acc += pred::detail::insphere_exact(pt(i), pt(i + 1), pt(i + 2), pt(i + 3), pt(i + 4));
  });
  // Coordinates spread over 2^-40..2^40 span more than 125 bits: the
  // expansions' raw form (their differences are inexact).
  std::vector<double> mixed(3 * 1024);
  for (double& x : mixed) x = r.at_exponent(r.range(-40, 40));
  auto mp = [&](int i) { return &mixed[3 * size_t(idx[i] % 1024)]; };
  const double t_raw = ns_per_call(exact_calls, [&] {
    for (int i = 0; i < exact_calls; ++i)
      acc += pred::detail::insphere_exact(mp(i), mp(i + 1), mp(i + 2), mp(i + 3), mp(i + 4));
  });
  const double t_raw_o = ns_per_call(exact_calls, [&] {
    for (int i = 0; i < exact_calls; ++i)
      acc += pred::detail::orient3d_exact(mp(i), mp(i + 1), mp(i + 2), mp(i + 3));
  });
  sink = acc;
  (void)sink;
  std::printf(
      "[predicates bench] ns/call on random points in the unit cube: orient3d %.2f (plain double "
      "%.2f), insphere %.2f (plain double %.2f); exact stage alone: insphere integer form "
      "on lattice points %.0f, on unit-cube doubles %.0f, raw form %.0f; orient3d raw form "
      "%.0f\n",
      t_o, t_plain_o, t_s, t_plain_s, t_exact, t_int53, t_raw, t_raw_o);
  SUCCEED();
}

// Thin configurations, where the filters' second stage (the computed
// permanent) decides what the column-sum bound cannot: points rounded onto
// a long segment (CAD split points) with one or two points slightly off it,
// at several offsets down to a few ulps. Every answer must match the oracle.
TEST_CASE("insphere and incircle are exact on thin configurations", "[predicates]") {
  Rng r(21);
  int decided_early = 0;
  for (int it = 0; it < 20000; ++it) {
    const P3 a = {r.sym(), r.sym(), r.sym()};
    const P3 b = {a[0] + 8 * r.sym(), a[1] + 8 * r.sym(), a[2] + 8 * r.sym()};
    const double offset = std::ldexp(1.0, -r.range(2, 50));
    std::array<P3, 5> p;
    for (int i = 0; i < 5; ++i) {
      const double t = r.unit();
      for (int k = 0; k < 3; ++k) p[i][k] = a[k] + t * (b[k] - a[k]);
      if (i >= 3 || r.range(0, 3) == 0)
        for (int k = 0; k < 3; ++k) p[i][k] += offset * r.sym();
    }
    const uint64_t exact_before = pred::counters().insphere_exact;
    SIGN_CHECK(pred::insphere(p[0].data(), p[1].data(), p[2].data(), p[3].data(), p[4].data()),
               insphere_q(p[0], p[1], p[2], p[3], p[4]), describe(p));
    decided_early += pred::counters().insphere_exact == exact_before;
    SIGN_CHECK(pred::incircle(p[0].data(), p[1].data(), p[2].data(), p[3].data()),
               incircle_q(p[0].data(), p[1].data(), p[2].data(), p[3].data()), describe(p));
  }
  CHECK(decided_early > 8000);  // 8562 here; 6916 without the second stage
}

// Bits spanned by the coordinates of the points: from the lowest set bit to
// the top of the largest magnitude (the integer forms' tiers: <= 62 one limb
// for most differences, <= 125 two limbs, beyond that the expansion forms).
int coordinate_span(const std::vector<const double*>& pts, int dim) {
  int lo = 1 << 20, hi = -(1 << 20);
  for (const double* p : pts)
    for (int k = 0; k < dim; ++k) {
      if (p[k] == 0) continue;
      int e;
      const double f = std::frexp(std::fabs(p[k]), &e);  // |x| < 2^e
      const uint64_t m = static_cast<uint64_t>(std::ldexp(f, 53));
      lo = std::min(lo, e - 53 + __builtin_ctzll(m)), hi = std::max(hi, e);
    }
  return hi - lo;
}

TEST_CASE("decimal CAD coordinates: exact zeros in every integer tier and beyond", "[predicates]") {
  // Five corners of an axis-parallel box are co-spherical, four of a face
  // co-planar and (projected) co-circular, whatever the rounding of their
  // decimal coordinates; one corner moved by an ulp now and then. Steps and
  // offsets spread the coordinates' bit span over the one-limb, two-limb and
  // expansion ranges of the exact stage.
  Rng r(23);
  const double steps[] = {0.1, 0.001, 25.4, 1e-7, 3.3e5, 0.30000000000000004};
  int classes[3] = {0, 0, 0}, zeros = 0;
  for (int it = 0; it < 30000; ++it) {
    double v[3][2];
    const double box_step = steps[r.range(0, 5)];  // one step: a narrow span
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 2; ++j) {
        const double h = it % 3 == 0 ? box_step : steps[r.range(0, 5)];
        v[k][j] = (r.range(-40, 40)) * h;
        if (it % 3 == 1 && r.range(0, 2) == 0) v[k][j] += 1e-12 * r.sym();
        if (it % 3 == 2 && r.range(0, 3) == 0) v[k][j] = std::ldexp(1.0 + r.unit(), -r.range(60, 200));
      }
    std::array<P3, 8> corner;
    for (int c = 0; c < 8; ++c)
      for (int k = 0; k < 3; ++k) corner[c][k] = v[k][(c >> k) & 1];
    std::array<P3, 5> p;
    int pick[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    for (int i = 0; i < 5; ++i) std::swap(pick[i], pick[r.range(i, 7)]);
    for (int i = 0; i < 5; ++i) p[i] = corner[pick[i]];
    if (r.range(0, 4) == 0) p[4][r.range(0, 2)] = bump(p[4][r.range(0, 2)], r.range(0, 1) ? 1 : -1);
    const std::vector<const double*> all = {p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                            p[4].data()};
    const int span = coordinate_span(all, 3);
    ++classes[span <= 62 ? 0 : span <= 125 ? 1 : 2];
    zeros += check_orient3d_insphere(p) == 0;
    // The face z = v[2][0]: corners 0..3 co-planar, co-circular in xy.
    const double* f[4] = {corner[0].data(), corner[1].data(), corner[3].data(), corner[2].data()};
    P3 moved = corner[2];
    if (it % 2) moved[0] = bump(moved[0], 1), f[3] = moved.data();
    SIGN_CHECK(pred::incircle(f[0], f[1], f[2], f[3]), incircle_q(f[0], f[1], f[2], f[3]),
               describe(p));
    SIGN_CHECK(pred::orient3d(f[0], f[1], f[2], p[4].data()),
               orient3d_q(corner[0], corner[1], corner[3], p[4]), describe(p));
  }
  CHECK(zeros > 10000);
  CHECK(classes[0] > 3000);
  CHECK(classes[1] > 3000);
  CHECK(classes[2] > 3000);
}

TEST_CASE("small-integer predicates match the oracle within their spread", "[predicates]") {
  // The promise of small_integer_points: integers spread over at most 2^9 per
  // axis. Co-spherical lattice points (exact zeros and their neighbours) and
  // random points filling the whole allowed spread, far from the origin too.
  Rng r(91);
  const auto& sphere = lattice_sphere();
  int zeros = 0;
  for (int it = 0; it < 20000; ++it) {
    std::array<P3, 5> p;
    const double base = it % 3 == 0 ? 0 : double(r.range(-1000000, 1000000));
    for (P3& q : p) {
      if (it % 2 == 0) {
        const P3& s = sphere[r.next() % sphere.size()];
        q = {s[0] + 21 + base, s[1] + 21 + base, s[2] + 21 + base};
      } else {
        for (double& x : q) x = base + r.range(0, 512);
        if (r.range(0, 3) == 0) q[r.range(0, 2)] = base + 512 * r.range(0, 1);
      }
    }
    std::vector<double> flat;
    for (const P3& q : p) flat.insert(flat.end(), q.begin(), q.end());
    REQUIRE(pred::small_integer_points(flat.data(), 5));
    const int s = pred::insphere_small_integers(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                                p[4].data());
    REQUIRE(s == insphere_q(p[0], p[1], p[2], p[3], p[4]));
    REQUIRE(pred::orient3d_small_integers(p[0].data(), p[1].data(), p[2].data(), p[3].data()) ==
            orient3d_q(p[0], p[1], p[2], p[3]));
    if (s == 0) {
      ++zeros;
      // The perturbation decides alike on either evaluation.
      const uint32_t ids[5] = {uint32_t(r.range(0, 9)), 10, 11, 12, 13};
      REQUIRE(pred::insphere_tie(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                 p[4].data(), ids[0], ids[1], ids[2], ids[3], ids[4], true) ==
              pred::insphere_tie(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                 p[4].data(), ids[0], ids[1], ids[2], ids[3], ids[4], false));
    }
  }
  CHECK(zeros > 1000);
}

TEST_CASE("incircle_coplanar_small_integers matches the oracle within the spread", "[predicates]") {
  // Four small-integer points in an axis-parallel plane (decided in doubles)
  // or in the plane x + y = const (passed on to incircle_coplanar): lattice
  // points of one circle (exact zeros) and random ones over the whole spread
  // of small_integer_points, far from the origin too.
  Rng r(77);
  std::vector<std::array<int, 2>> circle;  // x^2 + y^2 = 5525: 48 lattice points
  for (int x = -75; x <= 75; ++x)
    for (int y = -75; y <= 75; ++y)
      if (x * x + y * y == 5525) circle.push_back({x, y});
  REQUIRE(circle.size() >= 24);
  int zeros = 0, axis = 0, slanted = 0;
  for (int it = 0; it < 40000; ++it) {
    const double base = it % 3 == 0 ? 0 : double(r.range(-1000000, 1000000));
    const int k = r.range(0, 3);  // 3: the plane x + y = const
    const double level = base + r.range(0, 512);
    std::array<P3, 4> p;
    for (P3& q : p) {
      int u, v;
      if (it % 2 == 0) {
        const auto& c = circle[r.next() % circle.size()];
        u = c[0] + 200, v = c[1] + 200;
      } else {
        u = r.range(0, 512), v = r.range(0, 512);
      }
      if (k < 3) {
        q[k] = level;
        q[(k + 1) % 3] = base + u;
        q[(k + 2) % 3] = base + v;
      } else {
        q = {base + u, level - u, base + v};
      }
    }
    std::vector<double> flat;
    for (const P3& q : p) flat.insert(flat.end(), q.begin(), q.end());
    if (!pred::small_integer_points(flat.data(), 4)) continue;
    if (pred::collinear3d(p[0].data(), p[1].data(), p[2].data())) continue;
    const int s = pred::incircle_coplanar_small_integers(p[0].data(), p[1].data(), p[2].data(),
                                                         p[3].data());
    REQUIRE(s == incircle_coplanar_q(p[0], p[1], p[2], p[3]));
    (k < 3 ? axis : slanted) += 1;
    if (s == 0) {
      ++zeros;
      // The perturbation decides alike on either evaluation.
      const uint32_t ids[4] = {uint32_t(r.range(0, 9)), 10, 11, uint32_t(r.range(0, 12))};
      if (ids[3] == ids[0] || ids[3] == 10 || ids[3] == 11) continue;
      REQUIRE(pred::incircle_coplanar_sos_on_plane(p[0].data(), p[1].data(), p[2].data(),
                                                   p[3].data(), ids[0], ids[1], ids[2], ids[3],
                                                   true) ==
              pred::incircle_coplanar_sos_on_plane(p[0].data(), p[1].data(), p[2].data(),
                                                   p[3].data(), ids[0], ids[1], ids[2], ids[3]));
    }
  }
  CHECK(zeros > 2000);
  CHECK(axis > 20000);
  CHECK(slanted > 5000);
}

TEST_CASE("orient3d_in_box and insphere_in_box match the oracle for points of their box",
          "[predicates]") {
  // The static bounds are tightest when the points span the whole box and
  // are nearly degenerate: points on the sphere inscribed in the box
  // (rounded), the fifth moved off it by 2^-30 to 2^-60 of the box, and the
  // fourth moved off the plane of the first three alike; at scales from 2^-90
  // to 2^90, far from the origin too; random points as well. Both ways of
  // deciding occur (the bound decides, or the semi-static stages behind it).
  Rng r(57);
  int decided[2][2] = {{0, 0}, {0, 0}};  // [orient3d, insphere][by the bound]
  for (int it = 0; it < 20000; ++it) {
    const int e = r.range(-90, 90);
    const double scale = std::ldexp(1.0, e);
    const P3 centre = {r.range(0, 2) == 0 ? 0 : r.at_exponent(e + r.range(0, 20)),
                       r.sym() * scale, r.sym() * scale};
    std::array<P3, 5> p;
    for (int i = 0; i < 5; ++i) {
      if (it % 2 == 0) {
        // A random direction, on the sphere of radius scale around centre.
        double d[3] = {r.sym(), r.sym(), r.sym()};
        double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(len > 0.1)) d[0] = 1, d[1] = d[2] = 0, len = 1;
        const double lift = i == 4 ? 1 + std::ldexp(r.sym(), -r.range(30, 60)) : 1;
        for (int k = 0; k < 3; ++k) p[i][k] = centre[k] + scale * lift * d[k] / len;
      } else {
        for (int k = 0; k < 3; ++k) p[i][k] = centre[k] + scale * r.sym();
      }
    }
    if (it % 4 == 0) {
      // The fourth point near the plane of the first three.
      const double s = r.unit(), t = r.unit() * (1 - s);
      for (int k = 0; k < 3; ++k)
        p[3][k] = p[0][k] + s * (p[1][k] - p[0][k]) + t * (p[2][k] - p[0][k]) +
                  std::ldexp(r.sym(), -r.range(30, 60)) * scale;
    }
    // The box: the five points and, some of the time, two corners around them.
    std::vector<double> box;
    for (const P3& q : p) box.insert(box.end(), q.begin(), q.end());
    if (it % 3 == 0)
      for (double sgn : {-1.0, 1.0})
        for (int k = 0; k < 3; ++k) box.push_back(centre[k] + sgn * 2 * scale);
    const pred::BoxBounds bounds = pred::box_bounds(box.data(), box.size() / 3);
    REQUIRE(bounds.orient3d > 0);
    REQUIRE(bounds.insphere > 0);
    const int o = pred::orient3d_in_box(p[0].data(), p[1].data(), p[2].data(), p[3].data(), bounds);
    REQUIRE(o == orient3d_q(p[0], p[1], p[2], p[3]));
    const int s = pred::insphere_in_box(p[0].data(), p[1].data(), p[2].data(), p[3].data(),
                                        p[4].data(), bounds);
    REQUIRE(s == insphere_q(p[0], p[1], p[2], p[3], p[4]));
    // Which way decided: the same determinants as the predicates' own.
    const double od =
        pred::detail::orient3d_terms(p[0].data(), p[1].data(), p[2].data(), p[3].data()).det;
    const double sd = pred::detail::insphere_terms(p[0].data(), p[1].data(), p[2].data(),
                                                   p[3].data(), p[4].data()).det;
    ++decided[0][std::fabs(od) > bounds.orient3d];
    ++decided[1][std::fabs(sd) > bounds.insphere];
  }
  for (auto& d : decided) {
    CHECK(d[0] > 500);
    CHECK(d[1] > 1000);
  }
}

TEST_CASE("box_bounds are 0 outside their proven range", "[predicates]") {
  auto zero = [](const pred::BoxBounds& b) { return b.orient3d == 0 && b.insphere == 0; };
  std::vector<double> pts = {0, 0, 0, 1, 2, 3};
  CHECK(pred::box_bounds(pts.data(), 2).orient3d > 0);
  CHECK(pred::box_bounds(pts.data(), 2).insphere > 0);
  CHECK(zero(pred::box_bounds(pts.data(), 0)));
  pts[5] = 0;  // a flat box: zero width on z
  CHECK(zero(pred::box_bounds(pts.data(), 2)));
  pts = {0, 0, 0, 0x1p+101, 1, 1};  // wider than 2^100
  CHECK(zero(pred::box_bounds(pts.data(), 2)));
  pts = {0, 0, 0, 0x1p-101, 1, 1};  // narrower than 2^-100
  CHECK(zero(pred::box_bounds(pts.data(), 2)));
  pts = {0, 0, 0, 1, 1, HUGE_VAL};
  CHECK(zero(pred::box_bounds(pts.data(), 2)));
  pts = {0, 0, 0, 1, 1, 1, 2, std::nan(""), 2};
  CHECK(zero(pred::box_bounds(pts.data(), 3)));
}

TEST_CASE("small_integer_points rejects fractions, wide spreads and huge integers",
          "[predicates]") {
  std::vector<double> pts = {0, 0, 0, 512, 512, 512, 3, -0.0, 7};
  CHECK(pred::small_integer_points(pts.data(), 3));
  pts[4] = 512.5;
  CHECK_FALSE(pred::small_integer_points(pts.data(), 3));
  pts[4] = 513;
  CHECK_FALSE(pred::small_integer_points(pts.data(), 3));
  pts[4] = 512, pts[7] = -1;
  CHECK_FALSE(pred::small_integer_points(pts.data(), 3));  // spread 513 on y
  pts = {0x1p+52, 0x1p+52, 0x1p+52, 0x1p+52 + 2, 0x1p+52, 0x1p+52};
  CHECK_FALSE(pred::small_integer_points(pts.data(), 2));
  const double nan = std::nan("");
  pts = {0, 0, nan};
  CHECK_FALSE(pred::small_integer_points(pts.data(), 1));
  CHECK_FALSE(pred::small_integer_points(pts.data(), 0));
}

TEST_CASE("double-double: sums, products and quotients keep about 106 bits", "[predicates]") {
  // 1 + 2^-80 is not a double; its double-double is, and the 1 cancels.
  const DoubleDouble x = DoubleDouble(1) + std::ldexp(1.0, -80);
  CHECK((x - 1).value() == std::ldexp(1.0, -80));
  // (1 + 2^-30)^2 = 1 + 2^-29 + 2^-60: the last term is lost in doubles.
  const DoubleDouble y = DoubleDouble(1 + std::ldexp(1.0, -30));
  CHECK(((y * y) - 1 - std::ldexp(1.0, -29)).value() == std::ldexp(1.0, -60));
  // 1/3 times 3 is 1 within a few units of 2^-104.
  const DoubleDouble third = DoubleDouble(1) / 3;
  CHECK(std::fabs((third * 3 - 1).value()) < std::ldexp(1.0, -100));
  CHECK(third.hi == 1.0 / 3);
  CHECK(DoubleDouble(2) < DoubleDouble(2, 1e-300));
}
