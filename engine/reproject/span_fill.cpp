#include "reproject/span_fill.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace epsray {

corner_differences corner_differences_of(const glm::vec3 v[16]) {
  corner_differences d;
  for (int i = 0; i < 4; ++i) {
    d.d1[i] = glm::vec3(0);
    for (int j = 0; j < 4; ++j) d.d2[i][j] = glm::vec3(0);
  }
  for (int k = 0; k < 16; ++k) {
    for (int i = 0; i < 4; ++i) {
      const int bi = 1 << i;
      if (k & bi) continue;
      d.d1[i] = glm::max(d.d1[i], glm::abs(v[k | bi] - v[k]));
      for (int j = i + 1; j < 4; ++j) {
        const int bj = 1 << j;
        if (k & bj) continue;
        const glm::vec3 m = glm::abs(v[k | bi | bj] - v[k | bi] - v[k | bj] + v[k]);
        d.d2[i][j] = d.d2[j][i] = glm::max(d.d2[i][j], m);
      }
    }
  }
  return d;
}

span_bound span_error(const camera& cam, const cell_ref& c, const corner_differences& d, int y, int xa, int xb) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  const span_bound none{glm::vec3(inf), glm::vec3(inf)};
  const facepair& fp = c.lt->fp;
  const lt_node& n = *c.node;
  // The unnormalized eye direction along the row, D(x) = P + x Q (eye_direction's terms).
  const double cx = 0.5 * double(cam.width - 1), cy = 0.5 * double(cam.height - 1), step = cam.step;
  const glm::dvec3 Q = step * glm::dvec3(cam.r);
  const glm::dvec3 P = glm::dvec3(cam.w) - cx * Q + (cy - double(y)) * step * glm::dvec3(cam.u);
  const glm::dvec3 Da = P + double(xa) * Q, Db = P + double(xb) * Q;
  const int ax = fp.axis;
  // Both ends run towards the back plane, so D's axis component keeps its sign between
  // them (it is linear in x) and |1 / D_axis| is largest at an end.
  if (!(Da[ax] * Db[ax] > 0)) return none;
  const double m = std::max(1 / std::fabs(Da[ax]), 1 / std::fabs(Db[ax]));
  // The smallest |d_axis| of the unit direction: how much a direction's rounding moves a ratio.
  const double unit_axis = std::min(std::fabs(Da[ax]) / glm::length(Da), std::fabs(Db[ax]) / glm::length(Db));
  const glm::dvec3 o(cam.origin);
  const int along[4] = {fp.u, fp.v, fp.u, fp.v};
  const double plane[4] = {fp.front, fp.front, fp.back, fp.back};
  // Coordinate i is x4_i = o_e + K_i r_e(x), r_e = D_e / D_axis, and t_i = (x4_i - lo_i) / w_i:
  //   r_e' = C_e / D_axis^2, r_e'' = -2 Q_axis C_e / D_axis^3, C_e = Q_e P_axis - P_e Q_axis.
  double tp[4], tpp[4], dt[4];
  for (int i = 0; i < 4; ++i) {
    const int e = along[i];
    const double width = double(n.hi[i]) - double(n.lo[i]);
    if (!(width > 0)) return none;
    const double K = plane[i] - o[ax], k = std::fabs(K) / width;
    const double C = std::fabs(Q[e] * P[ax] - P[e] * Q[ax]);
    tp[i] = k * C * m * m;
    tpp[i] = 2 * k * std::fabs(Q[ax]) * C * m * m * m;
    // Float lines: eye_direction's unit vector is off by a few ulps per component (its sum
    // of three products and the normalization), which moves r_e by about
    // (1 + |r_e|) / |d_axis| of that; line_coords' own operations add a few ulps of |o_e|
    // and |x4_i|. 4e-6 covers both several times over (float's ulp at 1 is 1.2e-7); the
    // term is tiny next to a cell's own error.
    const double re = std::max(std::fabs(Da[e] / Da[ax]), std::fabs(Db[e] / Db[ax]));  // r_e is monotone
    const double x4 = std::fabs(o[e]) + std::fabs(K) * re;
    dt[i] = 4e-6 * ((1 + re) * std::fabs(K) / unit_axis + std::fabs(o[e]) + x4) / width;
  }
  span_bound b;
  for (int ch = 0; ch < 3; ++ch) {
    double m2 = 0, r = 0;
    for (int i = 0; i < 4; ++i) {
      m2 += double(d.d1[i][ch]) * tpp[i];
      r += double(d.d1[i][ch]) * dt[i];
      for (int j = 0; j < 4; ++j)
        if (j != i) m2 += double(d.d2[i][j][ch]) * tp[i] * tp[j];
    }
    // Rounded up on the way to float.
    b.m2[ch] = float(m2 * (1 + 1e-6)) + std::numeric_limits<float>::denorm_min();
    b.rounding[ch] = float(r * (1 + 1e-6)) + std::numeric_limits<float>::denorm_min();
  }
  if (!std::isfinite(b.m2.x + b.m2.y + b.m2.z + b.rounding.x + b.rounding.y + b.rounding.z)) return none;
  return b;
}

bool span_fillable(const cell_ref& c, const cell_trust& t) {
  return t.ok && t.count == 0 && !t.face_check && !c.ip->textured() && !(c.ip->deferred | c.ip->deferred_rays);
}

int fill_span(const camera& cam, const cell_ref& c, int y, int x0, int x1, int segment, float eps, glm::vec3* L,
              std::uint8_t* ok) {
  const interpolant& ip = *c.ip;
  const lt_node& n = *c.node;
  // An end pixel's value: the interpolant at its own line, which must lie in the cell (the
  // run between two such ends then does too: membership is an interval of x).
  auto end_value = [&](int x, glm::vec3& v) {
    float x4[4], t[4];
    if (!eye_line_in_cell(cam, c, x, y, x4)) return false;
    cell_fractions(n, x4, t);
    v = quadrilinear(ip.rad, t);
    return true;
  };
  const corner_differences d = corner_differences_of(ip.rad);
  int passed = 0;
  auto put = [&](int x, glm::vec3 v, glm::vec3 E) {
    L[x - x0] = v;
    ok[x - x0] = within(v, E, eps);
    passed += ok[x - x0];
  };
  int xa = x0;
  glm::vec3 La{0};
  bool have_a = end_value(xa, La);
  for (;;) {
    if (!have_a) {
      ok[xa - x0] = 0;
      if (xa == x1) break;
      ++xa;
      have_a = end_value(xa, La);
      continue;
    }
    put(xa, La, ip.err);
    if (xa == x1) break;
    const int xb = std::min(xa + std::max(segment, 1), x1);
    glm::vec3 Lb;
    if (!end_value(xb, Lb)) {
      for (int x = xa + 1; x < xb; ++x) ok[x - x0] = 0;
      xa = xb, have_a = false;
      continue;
    }
    const span_bound b = span_error(cam, c, d, y, xa, xb);
    const float inv = 1.0f / float(xb - xa);
    for (int x = xa + 1; x < xb; ++x) {
      const float f = float(x - xa) * inv;
      const float q = 0.5f * float(x - xa) * float(xb - x);
      put(x, La + f * (Lb - La), ip.err + q * b.m2 + 2.0f * b.rounding);
    }
    xa = xb, La = Lb;
  }
  return passed;
}

}  // namespace epsray
