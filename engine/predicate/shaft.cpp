#include "predicate/shaft.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace epsray {

namespace {

bool is_empty(const bounds& b) { return b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z; }

// The coordinate of the face of `b` on `axis` facing `sign` (+1: hi, -1: lo).
float face(const bounds& b, int axis, int sign) { return sign > 0 ? b.hi[axis] : b.lo[axis]; }

// Which box reaches farther along (axis, sign): 0 for A, 1 for B, -1 on a tie.
int reaches_farther(const bounds& a, const bounds& b, int axis, int sign) {
  float fa = float(sign) * face(a, axis, sign), fb = float(sign) * face(b, axis, sign);
  return fa > fb ? 0 : fb > fa ? 1 : -1;
}

// Smallest float >= x (x finite, |x| < FLT_MAX). Steps one ulp by hand: std::nextafter
// is a library call and made make_shaft several times slower.
float round_up(double x) {
  float f = float(x);
  if (double(f) >= x) return f;
  if (f == 0) return std::numeric_limits<float>::denorm_min();
  std::uint32_t u = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0 ? u + 1 : u - 1);
}

}  // namespace

shaft make_shaft(const bounds& a, const bounds& b) {
  shaft s;
  for (int k = 0; k < shaft_max_planes; ++k)
    s.nx[k] = s.ny[k] = s.nz[k] = 0, s.d[k] = std::numeric_limits<float>::infinity();
  const bool ea = is_empty(a), eb = is_empty(b);
  if (ea && eb) return s;  // default bounds: empty, culls every finite box
  bounds u = ea ? b : a;
  if (!ea && !eb) u.grow(b);

  // Slack relative to the largest coordinate (float error scales with it); never zero.
  float scale = 0;
  for (int i = 0; i < 3; ++i) scale = std::max(scale, std::max(std::fabs(u.lo[i]), std::fabs(u.hi[i])));
  const double pad = std::max(double(shaft_rel_tol) * double(scale), double(std::numeric_limits<float>::min()));
  for (int i = 0; i < 3; ++i) {
    s.box.lo[i] = -round_up(-(double(u.lo[i]) - pad));
    s.box.hi[i] = round_up(double(u.hi[i]) + pad);
  }
  if (ea || eb) return s;  // one box alone: its hull is its box

  // A plane joins the (d1, d2) edges of A and B when one box reaches farther along d1 and
  // the other along d2. P is the box reaching farther along d1, Q along d2.
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      for (int si = -1; si <= 1; si += 2)
        for (int sj = -1; sj <= 1; sj += 2) {
          int pi = reaches_farther(a, b, i, si), pj = reaches_farther(a, b, j, sj);
          // At most 8 such pairs exist; the guard only keeps a miscount from overflowing
          // (dropping a plane can only keep more boxes).
          if (pi < 0 || pj < 0 || pi == pj || s.planes == shaft_max_planes) continue;
          const bounds& p = pi == 0 ? a : b;
          const bounds& q = pi == 0 ? b : a;
          // In outward coordinates u = si * x_i, v = sj * x_j: P's edge (uP, vP), Q's (uQ, vQ)
          // with uP > uQ and vQ > vP; the outward normal (vQ - vP, uP - uQ) is positive in both.
          double pu = double(face(p, i, si)), pv = double(face(p, j, sj));
          double qu = double(face(q, i, si)), qv = double(face(q, j, sj));
          double ni = double(si) * (double(sj) * (qv - pv)), nj = double(sj) * (double(si) * (pu - qu));
          double len = std::sqrt(ni * ni + nj * nj);
          float fi = float(ni / len), fj = float(nj / len);
          // The offset is the larger of the two edges' values under the float normal (exact
          // products in double): with n_i of sign si (or 0), n_j of sign sj (or 0) and the
          // third component 0, both boxes reach their largest n . x on those edges, so
          // this half-space holds A and B whole whatever rounding did to the normal.
          double d = std::max(double(fi) * pu + double(fj) * pv, double(fi) * qu + double(fj) * qv) + pad;
          int k = s.planes++;
          float n[3] = {0, 0, 0};
          n[i] = fi, n[j] = fj;
          s.nx[k] = n[0], s.ny[k] = n[1], s.nz[k] = n[2];
          s.d[k] = round_up(d);
        }
  return s;
}

}  // namespace epsray
