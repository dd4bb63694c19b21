// Diagonal second-order jets: a quantity's enclosure over a 4D cell together with
// enclosures of its four first and four pure second partial derivatives. The pure second
// partials of sums, products and compositions need only pure terms
// ((fg)_ii = f_ii g + 2 f_i g_i + f g_ii; (phi o f)_ii = phi''(f) f_i^2 + phi'(f) f_ii), so one
// pass yields everything the multilinear interpolation bound
// |f - If| <= sum_i h_i^2 / 8 * max |f_ii| needs. T is interval or affine.
#pragma once
#include <algorithm>
#include <cmath>

#include "interp/interval.h"
#include "predicate/affine.h"

namespace epsray {

inline double lo(const interval& a) { return a.lo; }
inline double hi(const interval& a) { return a.hi; }

template <class T>
inline T unbounded_value();
template <>
inline interval unbounded_value<interval>() { return interval::entire(); }
template <>
inline affine unbounded_value<affine>() { return aff_detail::unbounded(); }

template <class T>
struct djet_t {
  static constexpr int n = 4;
  T v{0.0};
  T d[n] = {T(0.0), T(0.0), T(0.0), T(0.0)};
  T dd[n] = {T(0.0), T(0.0), T(0.0), T(0.0)};

  djet_t() = default;
  djet_t(double c) : v(c) {}  // NOLINT
  djet_t(T c) : v(c) {}       // NOLINT
};

template <class T>
djet_t<T> operator+(const djet_t<T>& a, const djet_t<T>& b) {
  djet_t<T> r(a.v + b.v);
  for (int i = 0; i < 4; ++i) r.d[i] = a.d[i] + b.d[i], r.dd[i] = a.dd[i] + b.dd[i];
  return r;
}
template <class T>
djet_t<T> operator-(const djet_t<T>& a) {
  djet_t<T> r(-a.v);
  for (int i = 0; i < 4; ++i) r.d[i] = -a.d[i], r.dd[i] = -a.dd[i];
  return r;
}
template <class T>
djet_t<T> operator-(const djet_t<T>& a, const djet_t<T>& b) {
  djet_t<T> r(a.v - b.v);
  for (int i = 0; i < 4; ++i) r.d[i] = a.d[i] - b.d[i], r.dd[i] = a.dd[i] - b.dd[i];
  return r;
}
template <class T>
djet_t<T> operator*(const djet_t<T>& a, const djet_t<T>& b) {
  djet_t<T> r(a.v * b.v);
  for (int i = 0; i < 4; ++i) {
    r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    r.dd[i] = a.dd[i] * b.v + (a.d[i] * b.d[i]) * 2.0 + a.v * b.dd[i];
  }
  return r;
}
template <class T>
djet_t<T> operator*(const djet_t<T>& a, double s) {
  djet_t<T> r(a.v * s);
  for (int i = 0; i < 4; ++i) r.d[i] = a.d[i] * s, r.dd[i] = a.dd[i] * s;
  return r;
}
template <class T>
djet_t<T> operator*(double s, const djet_t<T>& a) { return a * s; }
template <class T>
djet_t<T> operator+(const djet_t<T>& a, double s) {
  djet_t<T> r = a;
  r.v = a.v + s;
  return r;
}
template <class T>
djet_t<T> operator+(double s, const djet_t<T>& a) { return a + s; }
template <class T>
djet_t<T> operator-(const djet_t<T>& a, double s) { return a + (-s); }
template <class T>
djet_t<T> operator-(double s, const djet_t<T>& a) { return -a + s; }

template <class T>
djet_t<T> operator/(const djet_t<T>& a, const djet_t<T>& b) {
  T inv = T(1.0) / b.v;
  djet_t<T> r(a.v * inv);
  for (int i = 0; i < 4; ++i) {
    r.d[i] = (a.d[i] - r.v * b.d[i]) * inv;
    r.dd[i] = (a.dd[i] - (r.d[i] * b.d[i]) * 2.0 - r.v * b.dd[i]) * inv;
  }
  return r;
}
template <class T>
djet_t<T> operator/(const djet_t<T>& a, double s) { return a * (1.0 / s); }

// phi(f) given enclosures of phi, phi' and phi'' over f's range.
template <class T>
djet_t<T> compose(const djet_t<T>& f, const T& phi, const T& dphi, const T& ddphi) {
  djet_t<T> r(phi);
  for (int i = 0; i < 4; ++i) {
    r.d[i] = dphi * f.d[i];
    r.dd[i] = ddphi * sqr(f.d[i]) + dphi * f.dd[i];
  }
  return r;
}

template <class T>
djet_t<T> sqr(const djet_t<T>& f) { return compose(f, sqr(f.v), f.v * 2.0, T(2.0)); }

// sqrt(f) for f > 0 over the cell; where f may reach 0 the derivatives are unbounded.
template <class T>
djet_t<T> sqrt(const djet_t<T>& f) {
  if (!(lo(f.v) > 0)) return compose(f, sqrt(f.v), unbounded_value<T>(), unbounded_value<T>());
  T s = sqrt(f.v);
  T inv = T(1.0) / s;
  return compose(f, s, inv * 0.5, (inv * (T(1.0) / f.v)) * -0.25);
}

// f^k for f > 0 over the cell (k > 0).
template <class T>
djet_t<T> pow(const djet_t<T>& f, double k) {
  if (!(lo(f.v) > 0)) return compose(f, pow(f.v, k), unbounded_value<T>(), unbounded_value<T>());
  return compose(f, pow(f.v, k), pow(f.v, k - 1) * k, pow(f.v, k - 2) * (k * (k - 1)));
}

// The interpolation bound of one quantity: sum_i h_i^2 / 8 * max |f_ii|. Each axis' term
// is added to per_axis (which axes to halve when the bound is too large).
template <class T>
double interpolation_error(const djet_t<T>& f, const double h[4], double per_axis[4] = nullptr) {
  double e = 0;
  for (int i = 0; i < 4; ++i) {
    double m = std::max(std::fabs(lo(f.dd[i])), std::fabs(hi(f.dd[i])));
    double term = h[i] * h[i] / 8 * m;
    e += term;
    if (per_axis) per_axis[i] += term;
  }
  return std::isnan(e) ? INFINITY : e;
}

}  // namespace epsray
