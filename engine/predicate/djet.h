// Diagonal second-order jets over intervals: a quantity's enclosure over a 4D cell together
// with enclosures of its four first and four pure second partial derivatives. The pure
// second partials of sums, products and compositions need only pure terms
// ((fg)_ii = f_ii g + 2 f_i g_i + f g_ii; (phi o f)_ii = phi''(f) f_i^2 + phi'(f) f_ii), so one
// pass yields everything the multilinear interpolation bound
// |f - If| <= sum_i h_i^2 / 8 * max |f_ii| needs.
#pragma once
#include <algorithm>
#include <cmath>

#include "interp/interval.h"

namespace epsray {

struct djet {
  static constexpr int n = 4;
  interval v{0.0};
  interval d[n] = {interval(0.0), interval(0.0), interval(0.0), interval(0.0)};
  interval dd[n] = {interval(0.0), interval(0.0), interval(0.0), interval(0.0)};

  djet() = default;
  djet(double c) : v(c) {}
  djet(interval c) : v(c) {}
};

// Coordinate i varying over [lo, hi].
inline djet djet_variable(int i, double lo, double hi) {
  djet j(interval(lo, hi));
  j.d[i] = interval(1.0);
  return j;
}

inline djet operator+(const djet& a, const djet& b) {
  djet r(a.v + b.v);
  for (int i = 0; i < djet::n; ++i) r.d[i] = a.d[i] + b.d[i], r.dd[i] = a.dd[i] + b.dd[i];
  return r;
}
inline djet operator-(const djet& a, const djet& b) {
  djet r(a.v - b.v);
  for (int i = 0; i < djet::n; ++i) r.d[i] = a.d[i] - b.d[i], r.dd[i] = a.dd[i] - b.dd[i];
  return r;
}
inline djet operator-(const djet& a) {
  djet r(-a.v);
  for (int i = 0; i < djet::n; ++i) r.d[i] = -a.d[i], r.dd[i] = -a.dd[i];
  return r;
}
inline djet operator*(const djet& a, const djet& b) {
  djet r(a.v * b.v);
  for (int i = 0; i < djet::n; ++i) {
    r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    r.dd[i] = a.dd[i] * b.v + 2.0 * (a.d[i] * b.d[i]) + a.v * b.dd[i];
  }
  return r;
}
inline djet operator*(const djet& a, double s) {
  djet r(a.v * s);
  for (int i = 0; i < djet::n; ++i) r.d[i] = a.d[i] * s, r.dd[i] = a.dd[i] * s;
  return r;
}
inline djet operator*(double s, const djet& a) { return a * s; }
inline djet operator+(const djet& a, double s) {
  djet r = a;
  r.v = a.v + s;
  return r;
}
inline djet operator-(const djet& a, double s) { return a + (-s); }
inline djet operator-(double s, const djet& a) { return -a + s; }
inline djet operator+(double s, const djet& a) { return a + s; }

inline djet operator/(const djet& a, const djet& b) {
  djet r(a.v / b.v);
  for (int i = 0; i < djet::n; ++i) {
    r.d[i] = (a.d[i] - r.v * b.d[i]) / b.v;
    r.dd[i] = (a.dd[i] - 2.0 * (r.d[i] * b.d[i]) - r.v * b.dd[i]) / b.v;
  }
  return r;
}
inline djet operator/(const djet& a, double s) { return a * (1.0 / s); }

// phi(f) given enclosures of phi, phi' and phi'' over f's range.
inline djet compose(const djet& f, interval phi, interval dphi, interval ddphi) {
  djet r(phi);
  for (int i = 0; i < djet::n; ++i) {
    r.d[i] = dphi * f.d[i];
    r.dd[i] = ddphi * sqr(f.d[i]) + dphi * f.dd[i];
  }
  return r;
}

inline djet sqr(const djet& f) { return compose(f, sqr(f.v), 2.0 * f.v, interval(2.0)); }

// sqrt(f) for f > 0 over the cell; where f may reach 0 the derivatives are unbounded.
inline djet sqrt(const djet& f) {
  if (!(f.v.lo > 0)) return compose(f, sqrt(f.v), interval::entire(), interval::entire());
  interval s = sqrt(f.v);
  interval ds = 0.5 / s;
  interval dds = -0.25 / (s * f.v);
  return compose(f, s, ds, dds);
}

// f^k for f > 0 over the cell (k > 0).
inline djet pow(const djet& f, double k) {
  if (!(f.v.lo > 0)) return compose(f, pow(f.v, k), interval::entire(), interval::entire());
  return compose(f, pow(f.v, k), k * pow(f.v, k - 1), k * (k - 1) * pow(f.v, k - 2));
}

// The interpolation bound of one quantity: sum_i h_i^2 / 8 * max |f_ii|.
inline double interpolation_error(const djet& f, const double h[4]) {
  double e = 0;
  for (int i = 0; i < djet::n; ++i) {
    double m = std::max(std::fabs(f.dd[i].lo), std::fabs(f.dd[i].hi));
    e += h[i] * h[i] / 8 * m;
  }
  return e;
}

}  // namespace epsray
