// Second-order Taylor jets along one variable: (value, first derivative, second derivative).
//
// jet<T> with T = double gives exact (to rounding) derivatives at a point; with T = interval
// every component is an enclosure over a box of the variable, so jet<interval> bounds the
// second derivative of a formula over the box. The same operator templates serve both
// (and T = long double, useful as a reference).
//
// Rules: (f g)'' = f'' g + 2 f' g' + f g''
//        q = f / g:    q' = (f' - q g') / g,  q'' = (f'' - 2 q' g' - q g'') / g
//        s = sqrt(f):  s' = f' / (2 s),       s'' = (f'' - 2 s'^2) / (2 s)
//        p = f^k:      p' = k f^(k-1) f',     p'' = k (k-1) f^(k-2) f'^2 + k f^(k-1) f''
// Where a derivative does not exist or is unbounded somewhere in the box (sqrt at 0, f^k with
// k < 1 or k < 2 at 0, the kink of max(0, x)), that component is "unbounded": entire() for
// intervals, NaN for floating-point T. The value component stays a valid enclosure. An
// unbounded component times an exact [0, 0] gives 0 (interval 0 * inf = 0): right for a true
// constant factor, the only way an exact [0, 0] arises over a box of positive width.
//
// A jet is an aggregate: jet<T>{c} is the constant c (d = dd = 0), as is jet_constant(c).
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>

#include "interp/interval.h"

namespace epsray {

template <class T>
struct jet {
  T v{}, d{}, dd{};  // value, first derivative, second derivative
};

template <class T>
inline constexpr jet<T> jet_variable(T value) {
  return {value, T(1.0), T(0.0)};
}
template <class T>
inline constexpr jet<T> jet_constant(T value) {
  return {value, T(0.0), T(0.0)};
}

namespace jet_detail {

template <class T>
inline constexpr bool is_interval = std::is_same_v<T, interval>;

// Bounds of a component (a point for floating-point T).
inline double lower(const interval& x) { return x.lo; }
inline double upper(const interval& x) { return x.hi; }
template <class F>
  requires std::is_floating_point_v<F>
inline F lower(F x) {
  return x;
}
template <class F>
  requires std::is_floating_point_v<F>
inline F upper(F x) {
  return x;
}

template <class T>
inline T unbounded() {
  if constexpr (is_interval<T>)
    return entire();
  else
    return std::numeric_limits<T>::quiet_NaN();
}

// hull(x, 0): only reached for intervals (a point cannot straddle 0).
template <class T>
inline T join0(const T& x) {
  if constexpr (is_interval<T>)
    return hull(x, interval(0.0));
  else
    return x;
}

// Value functions with the interval library's domain clamping (x < 0 treated as 0).
inline interval sqr_(const interval& x) { return sqr(x); }
inline interval sqrt_(const interval& x) { return sqrt(x); }
inline interval pow_(const interval& x, double k) { return pow(x, k); }
template <class F>
  requires std::is_floating_point_v<F>
inline F sqr_(F x) {
  return x * x;
}
template <class F>
  requires std::is_floating_point_v<F>
inline F sqrt_(F x) {
  return std::sqrt(x > 0 ? x : F(0));
}
template <class F>
  requires std::is_floating_point_v<F>
inline F pow_(F x, double k) {
  if (k == 0) return F(1);
  if (!(x > 0)) return k > 0 ? F(0) : std::numeric_limits<F>::infinity();
  return std::pow(x, F(k));
}

}  // namespace jet_detail

// ---- jet (op) jet ----------------------------------------------------------------------------
template <class T>
inline jet<T> operator+(const jet<T>& a) {
  return a;
}
template <class T>
inline jet<T> operator-(const jet<T>& a) {
  return {-a.v, -a.d, -a.dd};
}
template <class T>
inline jet<T> operator+(const jet<T>& a, const jet<T>& b) {
  return {a.v + b.v, a.d + b.d, a.dd + b.dd};
}
template <class T>
inline jet<T> operator-(const jet<T>& a, const jet<T>& b) {
  return {a.v - b.v, a.d - b.d, a.dd - b.dd};
}
template <class T>
inline jet<T> operator*(const jet<T>& a, const jet<T>& b) {
  return {a.v * b.v, a.d * b.v + a.v * b.d, a.dd * b.v + 2.0 * (a.d * b.d) + a.v * b.dd};
}
template <class T>
inline jet<T> operator/(const jet<T>& a, const jet<T>& b) {
  T q = a.v / b.v;
  T dq = (a.d - q * b.d) / b.v;
  T ddq = (a.dd - 2.0 * (dq * b.d) - q * b.dd) / b.v;
  return {q, dq, ddq};
}

// ---- jet (op) scalar, scalar = T -------------------------------------------------------------
// std::type_identity_t keeps T deduced from the jet alone, so a double converts to interval.
template <class T>
inline jet<T> operator+(const jet<T>& a, const std::type_identity_t<T>& s) {
  return {a.v + s, a.d, a.dd};
}
template <class T>
inline jet<T> operator+(const std::type_identity_t<T>& s, const jet<T>& a) {
  return {s + a.v, a.d, a.dd};
}
template <class T>
inline jet<T> operator-(const jet<T>& a, const std::type_identity_t<T>& s) {
  return {a.v - s, a.d, a.dd};
}
template <class T>
inline jet<T> operator-(const std::type_identity_t<T>& s, const jet<T>& a) {
  return {s - a.v, -a.d, -a.dd};
}
template <class T>
inline jet<T> operator*(const jet<T>& a, const std::type_identity_t<T>& s) {
  return {a.v * s, a.d * s, a.dd * s};
}
template <class T>
inline jet<T> operator*(const std::type_identity_t<T>& s, const jet<T>& a) {
  return {s * a.v, s * a.d, s * a.dd};
}
template <class T>
inline jet<T> operator/(const jet<T>& a, const std::type_identity_t<T>& s) {
  return {a.v / s, a.d / s, a.dd / s};
}
template <class T>
inline jet<T> operator/(const std::type_identity_t<T>& s, const jet<T>& g) {
  T q = s / g.v;
  T dq = -(q * g.d) / g.v;
  T ddq = -(2.0 * (dq * g.d) + q * g.dd) / g.v;
  return {q, dq, ddq};
}

// ---- jet (op) double, for T != double (cheaper than converting the double to T) --------------
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator+(const jet<T>& a, double s) {
  return {a.v + s, a.d, a.dd};
}
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator+(double s, const jet<T>& a) {
  return {s + a.v, a.d, a.dd};
}
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator-(const jet<T>& a, double s) {
  return {a.v - s, a.d, a.dd};
}
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator-(double s, const jet<T>& a) {
  return {s - a.v, -a.d, -a.dd};
}
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator*(const jet<T>& a, double s) {
  return {a.v * s, a.d * s, a.dd * s};
}
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator*(double s, const jet<T>& a) {
  return {s * a.v, s * a.d, s * a.dd};
}
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator/(const jet<T>& a, double s) {
  return {a.v / s, a.d / s, a.dd / s};
}
template <class T>
  requires(!std::is_same_v<T, double>)
inline jet<T> operator/(double s, const jet<T>& g) {
  T q = s / g.v;
  T dq = -(q * g.d) / g.v;
  T ddq = -(2.0 * (dq * g.d) + q * g.dd) / g.v;
  return {q, dq, ddq};
}

// ---- compound assignment -----------------------------------------------------------------------
template <class T, class U>
inline jet<T>& operator+=(jet<T>& a, const U& b) {
  return a = a + b;
}
template <class T, class U>
inline jet<T>& operator-=(jet<T>& a, const U& b) {
  return a = a - b;
}
template <class T, class U>
inline jet<T>& operator*=(jet<T>& a, const U& b) {
  return a = a * b;
}
template <class T, class U>
inline jet<T>& operator/=(jet<T>& a, const U& b) {
  return a = a / b;
}

// ---- functions ---------------------------------------------------------------------------------
template <class T>
inline jet<T> sqr(const jet<T>& f) {
  using namespace jet_detail;
  return {sqr_(f.v), 2.0 * (f.v * f.d), 2.0 * (sqr_(f.d) + f.v * f.dd)};
}

// sqrt(f), value clamped to f >= 0 like the interval sqrt. Where f may reach 0 (lower bound
// <= 0) the derivatives are unbounded.
template <class T>
inline jet<T> sqrt(const jet<T>& f) {
  using namespace jet_detail;
  T s = sqrt_(f.v);
  if (!(lower(f.v) > 0)) return {s, unbounded<T>(), unbounded<T>()};
  T two_s = 2.0 * s;
  T ds = f.d / two_s;
  T dds = (f.dd - 2.0 * sqr_(ds)) / two_s;
  return {s, ds, dds};
}

// f^k for k >= 0 with the interval library's semantics: the function is max(0, f)^k.
//   k == 0: the constant 1.
//   f entirely < 0: 0 (all components).
//   f' where f may reach 0: unbounded if k < 1; for k >= 1 the formula, joined with 0 where f
//     may be negative (the clamped part has derivative 0).
//   f'' where f may reach 0: unbounded if k < 2 (for k == 1: unbounded only if f may be
//     negative, a kink; with f >= 0 it is f''); for k >= 2 the formula, joined with 0 where f
//     may be negative.
// k < 0 is accepted for f > 0; where f may reach 0 everything is unbounded.
template <class T>
inline jet<T> pow(const jet<T>& f, double k) {
  using namespace jet_detail;
  if (k == 0) return {T(1.0), T(0.0), T(0.0)};
  const auto lo = lower(f.v), hi = upper(f.v);
  if (k < 0 && !(lo > 0)) return {unbounded<T>(), unbounded<T>(), unbounded<T>()};
  if (hi < 0) return {T(0.0), T(0.0), T(0.0)};
  const bool touches = !(lo > 0);  // f may be 0 (or negative) somewhere in the box
  const bool crosses = lo < 0;     // the clamp max(0, f) is active somewhere in the box
  T v = pow_(f.v, k);
  if (k == 1) {
    if (crosses) return {v, join0(f.d), unbounded<T>()};
    return f;
  }
  T d, dd;
  if (k < 1 && touches) {
    d = unbounded<T>();
  } else {
    d = k * (pow_(f.v, k - 1) * f.d);
    if (crosses) d = join0(d);
  }
  if (k < 2 && touches) {
    dd = unbounded<T>();
  } else {
    dd = (k * (k - 1)) * (pow_(f.v, k - 2) * sqr_(f.d)) + k * (pow_(f.v, k - 1) * f.dd);
    if (crosses) dd = join0(dd);
  }
  return {v, d, dd};
}

// max(0, f), for highlights. Value entirely >= 0: f. Entirely <= 0: the constant 0.
// Otherwise (the box straddles the kink) the value is [0, hi] and both derivatives are
// unbounded: max(0, x) has no derivative at the kink and the second derivative there is a
// Dirac spike, so no finite enclosure of f'' exists for such a box.
// For a lobe max(0, f)^k prefer pow(f, k): pow already means max(0, f)^k, and for k >= 2 it
// keeps f'' finite on boxes across the lobe's edge, where pow(max0(f), k) is unbounded.
template <class T>
inline jet<T> max0(const jet<T>& f) {
  using namespace jet_detail;
  if (lower(f.v) >= 0) return f;
  if (upper(f.v) <= 0) return {T(0.0), T(0.0), T(0.0)};
  if constexpr (is_interval<T>)
    return {interval(0.0, f.v.hi), unbounded<T>(), unbounded<T>()};
  else
    return f;  // unreachable: a point is either >= 0 or <= 0
}

}  // namespace epsray
