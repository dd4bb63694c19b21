// Affine arithmetic (Stolfi & de Figueiredo) over the 4 coordinates of a linetree cell:
// x = c + sum_i x_i e_i +- r, with e_i in [-1, 1] the cell coordinates rescaled and r a
// radius that absorbs every non-linearity and rounding error. Plain intervals forget that
// two quantities depend on the same coordinates, so over a wide cell their bounds grow
// with the cell's width; affine forms keep the first-order correlation and their excess
// shrinks with the square of the width. Every operation here is conservative: the true
// value for each point of the cell lies in the form's range.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

namespace epsray {

struct affine {
  static constexpr int n = 4;
  double c = 0;
  double x[n] = {0, 0, 0, 0};
  double r = 0;  // >= 0, or +inf for "unbounded"

  affine() = default;
  affine(double v) : c(v) {}  // NOLINT: constants mix freely with forms

  double radius() const {
    double s = r;
    for (int i = 0; i < n; ++i) s += std::fabs(x[i]);
    return s;
  }
};

namespace aff_detail {
// Slack for the rounding of one operation: a few ulps of the magnitudes involved.
inline double slack(double magnitude) { return magnitude * 4.5e-16 + 1e-300; }
inline bool bad(double v) { return !std::isfinite(v); }
inline affine unbounded() {
  affine a;
  a.r = std::numeric_limits<double>::infinity();
  return a;
}
inline affine fix(affine a) {  // NaN or inf anywhere: unbounded
  bool b = bad(a.c) || std::isnan(a.r);
  for (double v : a.x) b = b || bad(v);
  return b ? unbounded() : a;
}
}  // namespace aff_detail

inline double lo(const affine& a) { return a.c - a.radius(); }
inline double hi(const affine& a) { return a.c + a.radius(); }
inline double mid(const affine& a) { return a.c; }

// Coordinate i of the cell, ranging over [l, h].
inline affine affine_variable(int i, double l, double h) {
  affine a(0.5 * (l + h));
  a.x[i] = 0.5 * (h - l);
  a.r = aff_detail::slack(std::fabs(l) + std::fabs(h));
  return a;
}

// Some value in [l, h], with no known dependence on the coordinates.
inline affine affine_range(double l, double h) {
  affine a(0.5 * (l + h));
  a.r = 0.5 * (h - l) + aff_detail::slack(std::fabs(l) + std::fabs(h)) * 2;
  return aff_detail::fix(a);
}

inline affine operator+(const affine& a, const affine& b) {
  affine s(a.c + b.c);
  double mag = std::fabs(s.c);
  for (int i = 0; i < affine::n; ++i) s.x[i] = a.x[i] + b.x[i], mag += std::fabs(s.x[i]);
  s.r = a.r + b.r + aff_detail::slack(mag);
  return aff_detail::fix(s);
}
inline affine operator-(const affine& a) {
  affine s(-a.c);
  for (int i = 0; i < affine::n; ++i) s.x[i] = -a.x[i];
  s.r = a.r;
  return s;
}
inline affine operator-(const affine& a, const affine& b) { return a + (-b); }
inline affine operator*(const affine& a, double k) {
  affine s(a.c * k);
  double mag = std::fabs(s.c);
  for (int i = 0; i < affine::n; ++i) s.x[i] = a.x[i] * k, mag += std::fabs(s.x[i]);
  s.r = a.r * std::fabs(k) + aff_detail::slack(mag);
  return aff_detail::fix(s);
}
inline affine operator*(double k, const affine& a) { return a * k; }
inline affine operator+(const affine& a, double k) {
  affine s = a;
  s.c = a.c + k;
  s.r = a.r + aff_detail::slack(std::fabs(s.c));
  return aff_detail::fix(s);
}
inline affine operator+(double k, const affine& a) { return a + k; }
inline affine operator-(const affine& a, double k) { return a + (-k); }
inline affine operator-(double k, const affine& a) { return (-a) + k; }

inline affine operator*(const affine& a, const affine& b) {
  affine s(a.c * b.c);
  double la = 0, lb = 0, mag = std::fabs(s.c);
  for (int i = 0; i < affine::n; ++i) {
    s.x[i] = a.c * b.x[i] + b.c * a.x[i];
    la += std::fabs(a.x[i]), lb += std::fabs(b.x[i]);
    mag += std::fabs(a.c * b.x[i]) + std::fabs(b.c * a.x[i]);
  }
  // (c + X + A)(d + Y + B) - cd - cY - dX = XY + XB + AY + AB + cB + dA.
  s.r = la * lb + la * b.r + a.r * lb + a.r * b.r + std::fabs(a.c) * b.r + std::fabs(b.c) * a.r;
  s.r += aff_detail::slack(mag + s.r);
  return aff_detail::fix(s);
}

// phi over the range [l, h] of a as its tangent at the midpoint m plus a remainder:
// phi(x) in phi(m) + phi'(m)(x - m) +- max|phi''| (h - l)^2 / 8.
inline affine linearize(const affine& a, double phi_m, double dphi_m, double max_ddphi) {
  double l = lo(a), h = hi(a);
  if (!std::isfinite(l) || !std::isfinite(h) || !std::isfinite(max_ddphi)) return aff_detail::unbounded();
  double m = a.c;
  affine s = (a - m) * dphi_m + phi_m;
  double w = h - l;
  s.r += max_ddphi * (1 + 1e-12) * w * w / 8 + aff_detail::slack(std::fabs(phi_m) + std::fabs(dphi_m) * w) * 4;
  return aff_detail::fix(s);
}

// a's range with its ends rounded outwards: lo and hi are sums whose rounding the secant
// form below, tight at both ends, must not miss (1/x is steep near 0).
inline void outer_range(const affine& a, double& l, double& h) {
  const double pad = (std::fabs(a.c) + a.radius()) * 2e-15;
  l = lo(a) - pad, h = hi(a) + pad;
}

// phi over [l, h] (holding a's range) by its secant (the min-range approximation):
// g(x) = phi(x) - phi(l) - alpha (x - l) is convex or concave there, so its range is
// spanned by g(l) = 0, g(h) and g at x_star, where phi'(x_star) = alpha (x_of_slope).
// Over a wide range, where phi'' varies by orders of magnitude (1/x, sqrt near 0), the
// tangent's remainder is far looser: a direction normalized over a wide cell came out
// unbounded.
template <class Phi, class XOfSlope>
inline affine linearize_secant(const affine& a, double l, double h, Phi&& phi, XOfSlope&& x_of_slope) {
  const double w = h - l, pl = phi(l), ph = phi(h), alpha = (ph - pl) / w;
  if (!(w > 0) || !std::isfinite(pl) || !std::isfinite(ph) || !std::isfinite(alpha)) return aff_detail::unbounded();
  auto g = [&](double x) { return phi(x) - pl - alpha * (x - l); };
  const double gh = g(h), xs = x_of_slope(alpha);
  double glo = std::min(0.0, gh), ghi = std::max(0.0, gh);
  if (xs > l && xs < h) glo = std::min(glo, g(xs)), ghi = std::max(ghi, g(xs));
  affine s = (a - l) * alpha + (pl + 0.5 * (glo + ghi));
  s.r += 0.5 * (ghi - glo) +
         aff_detail::slack(std::fabs(pl) + std::fabs(ph) + std::fabs(alpha) * (std::fabs(l) + std::fabs(h))) * 16;
  return aff_detail::fix(s);
}

// The narrower of the tangent and secant forms (both enclose phi over a's range).
inline affine narrower(const affine& tangent, const affine& secant) {
  return secant.radius() < tangent.radius() ? secant : tangent;
}

// 1/a for a range not containing 0.
inline affine recip(const affine& a) {
  double l = lo(a), h = hi(a);
  if (!(l > 0 || h < 0)) return aff_detail::unbounded();
  double m = a.c, near = std::min(std::fabs(l), std::fabs(h));
  affine t = linearize(a, 1 / m, -1 / (m * m), 2 / (near * near * near));
  double ol, oh;
  outer_range(a, ol, oh);
  if (!(ol > 0 || oh < 0)) return t;
  const double side = l > 0 ? 1.0 : -1.0;  // 1/x' = alpha = -1/x^2 at x = side / sqrt(-alpha)
  return narrower(t, linearize_secant(a, ol, oh, [](double x) { return 1 / x; },
                                      [side](double alpha) { return side / std::sqrt(-alpha); }));
}
inline affine operator/(const affine& a, const affine& b) { return a * recip(b); }
inline affine operator/(const affine& a, double k) { return a * (1 / k); }
inline affine operator/(double k, const affine& a) { return recip(a) * k; }

inline affine sqr(const affine& a) { return a * a; }

// sqrt for a range > 0.
inline affine sqrt(const affine& a) {
  double l = lo(a);
  if (!(l > 0)) return aff_detail::unbounded();
  double m = a.c, sm = std::sqrt(m);
  affine t = linearize(a, sm, 0.5 / sm, 0.25 / (l * std::sqrt(l)));
  double ol, oh;
  outer_range(a, ol, oh);
  if (!(ol > 0)) return t;
  return narrower(t, linearize_secant(a, ol, oh, [](double x) { return std::sqrt(x); },
                                      [](double alpha) { return 0.25 / (alpha * alpha); }));
}

// a^k for a range > 0.
inline affine pow(const affine& a, double k) {
  if (k == 0) return affine(1.0);
  if (k == 1) return a;
  double l = lo(a), h = hi(a);
  if (!(l > 0)) return aff_detail::unbounded();
  double m = a.c;
  // |phi''| = |k (k - 1)| x^(k-2) is monotone in x: its max is at one end.
  double dd = std::fabs(k * (k - 1)) * std::max(std::pow(l, k - 2), std::pow(h, k - 2));
  affine t = linearize(a, std::pow(m, k), k * std::pow(m, k - 1), dd * (1 + 1e-12));
  double ol, oh;
  outer_range(a, ol, oh);
  if (!(ol > 0)) return t;
  return narrower(t, linearize_secant(a, ol, oh, [k](double x) { return std::pow(x, k); },
                                      [k](double alpha) { return std::pow(alpha / k, 1 / (k - 1)); }));
}

}  // namespace epsray
