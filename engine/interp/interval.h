// Closed intervals of doubles with outward rounding: the enclosures behind the error predicate.
//
// CONTRACT. An interval [lo, hi] stands for the set of reals x with lo <= x <= hi (an infinite
// bound means "unbounded on that side"; [-inf, +inf] is entire()). Every operation returns an
// interval that contains the exact real result of the operation for every choice of real
// operands inside its arguments, despite floating-point rounding. To get there each bound
// is computed in round-to-nearest and then moved one ulp outwards (std::nextafter towards
// -inf / +inf) unless the operation is detectably exact:
//   * a zero operand of + - * /, and a sum that comes out 0 (always exact in IEEE), are not
//     widened, so signs survive: [0, 1] * 2 + 0 is [0, 2+], never [-denorm, ...];
//   * sqrt: exact squares (sqrt(4) = 2) are detected;
//   * min, max, abs, hull, unary minus are exact;
//   * pow: glibc's pow is not correctly rounded (< 1 ulp), so its bounds move 2 ulps out.
// Other exact results (1 + 2, 2 * 3) are still widened: detecting them (TwoSum, significand
// lengths) made the jet<interval> ray-sphere evaluation ~1.7x slower for no benefit on boxes.
// NaN never comes out (for non-NaN inputs; a NaN passed to a constructor becomes unbounded):
//   * 0 * inf is taken as 0, as interval libraries do: an interval holds reals only, so an
//     infinite bound multiplied by an exact zero contributes 0;
//   * inf - inf (or -inf + inf) in a bound yields that side's infinity, i.e. entire();
//   * division by an interval containing 0 gives entire(); sqrt and pow clamp x to >= 0.
//
// Requires IEEE-754 doubles in round-to-nearest (the default) and no -ffast-math.
// FMA contraction (-mfma with GCC's default -ffp-contract=fast) is harmless: a rounded product
// is never added without first being widened (only exact zeros pass through).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#if defined(__FAST_MATH__)
#error "interp/interval.h needs IEEE semantics (no -ffast-math / -ffinite-math-only)"
#endif

namespace epsray {

namespace ivl_detail {

inline constexpr double inf = std::numeric_limits<double>::infinity();
inline constexpr double dbl_min = std::numeric_limits<double>::min();  // smallest normal

// == std::nextafter(x, +inf) for x that is not NaN, without the library call and without
// data-dependent branches (the sign of a bound is unpredictable): step the bit pattern up by one
// for x >= 0, down by one for x < 0; -0 is first turned into +0, +inf stays.
constexpr double next_up(double x) noexcept {
  x += 0.0;  // -0 -> +0 (not folded away: IEEE semantics)
  auto u = std::bit_cast<std::uint64_t>(x);
  double r = std::bit_cast<double>(u + 1 - ((u >> 63) << 1));
  return x == inf ? x : r;
}
// == std::nextafter(x, -inf) for x that is not NaN.
constexpr double next_down(double x) noexcept { return -next_up(-x); }

// Number of bits from the leading to the trailing 1 of x's significand (x finite, nonzero).
constexpr int odd_bits(double x) noexcept {
  auto u = std::bit_cast<std::uint64_t>(x);
  std::uint64_t m = u & ((std::uint64_t(1) << 52) - 1);
  if ((u >> 52 & 0x7ff) != 0) m |= std::uint64_t(1) << 52;  // normal: implicit bit
  m >>= std::countr_zero(m);
  return std::bit_width(m);
}

// Sum rounded down / up: one ulp out unless exact (a zero operand, or a zero sum);
// inf - inf gives that side's infinity. (The branches are predictable per call site: measured
// faster than computing both results and selecting.)
inline double add_dn(double a, double b) noexcept {
  if (b == 0) return a;
  if (a == 0) return b;
  double s = a + b;
  if (s != s) return -inf;  // inf - inf
  if (s == 0) return s;
  return next_down(s);
}
inline double add_up(double a, double b) noexcept {
  if (b == 0) return a;
  if (a == 0) return b;
  double s = a + b;
  if (s != s) return inf;
  if (s == 0) return s;
  return next_up(s);
}

// Product rounded down / up; an exact zero factor gives 0 (so 0 * inf = 0).
inline double mul_dn(double x, double y) noexcept {
  if (x == 0 || y == 0) return 0.0;
  return next_down(x * y);
}
inline double mul_up(double x, double y) noexcept {
  if (x == 0 || y == 0) return 0.0;
  return next_up(x * y);
}

// Quotient rounded down / up, y != 0. A finite x over an infinite y is taken as exactly 0
// (the infimum / supremum over the reals of the interval); inf / inf gives that side's infinity.
inline double div_dn(double x, double y) noexcept {
  if (x == 0) return 0.0;
  double q = x / y;
  if (q != q) return -inf;  // inf / inf
  if (std::isinf(y)) return 0.0;
  return next_down(q);
}
inline double div_up(double x, double y) noexcept {
  if (x == 0) return 0.0;
  double q = x / y;
  if (q != q) return inf;
  if (std::isinf(y)) return 0.0;
  return next_up(q);
}

// sqrt(x) for x >= 0 rounded down / up. It is exact when s has at most 26 significant bits
// (so s * s is exact) and s * s == x with x normal.
inline bool exact_sqrt(double x, double s) noexcept {
  return x >= 4 * dbl_min && x <= std::numeric_limits<double>::max() && odd_bits(s) <= 26 &&
         s * s == x;
}
inline double sqrt_dn(double x) noexcept {
  if (!(x > 0)) return 0.0;
  double s = std::sqrt(x);
  if (std::isinf(s) || exact_sqrt(x, s)) return s;
  return std::max(0.0, next_down(s));
}
inline double sqrt_up(double x) noexcept {
  if (!(x > 0)) return 0.0;
  double s = std::sqrt(x);
  if (std::isinf(s) || exact_sqrt(x, s)) return s;
  return next_up(s);
}

// x^k for x >= 0, k != 0, rounded down / up. pow is not correctly rounded: 2 ulps.
inline double pow_dn(double x, double k) noexcept {
  if (x == 1) return 1.0;
  if (x == 0) return k > 0 ? 0.0 : inf;
  if (std::isinf(x)) return k > 0 ? inf : 0.0;
  return std::max(0.0, next_down(next_down(std::pow(x, k))));
}
inline double pow_up(double x, double k) noexcept {
  if (x == 1) return 1.0;
  if (x == 0) return k > 0 ? 0.0 : inf;
  if (std::isinf(x)) return k > 0 ? inf : 0.0;
  return next_up(next_up(std::pow(x, k)));
}

}  // namespace ivl_detail

struct interval {
  double lo, hi;  // lo <= hi; never NaN

  constexpr interval() noexcept : lo(0.0), hi(0.0) {}
  // Degenerate [x, x]; NaN becomes entire.
  constexpr interval(double x) noexcept  // NOLINT(google-explicit-constructor): on purpose
      : lo(x == x ? x : -ivl_detail::inf), hi(x == x ? x : ivl_detail::inf) {}
  // [lo, hi]; the caller keeps lo <= hi. A NaN bound becomes unbounded on its side.
  constexpr interval(double lo_, double hi_) noexcept
      : lo(lo_ == lo_ ? lo_ : -ivl_detail::inf), hi(hi_ == hi_ ? hi_ : ivl_detail::inf) {}

  static constexpr interval entire() noexcept { return {-ivl_detail::inf, ivl_detail::inf}; }

  constexpr bool operator==(const interval&) const = default;

  interval& operator+=(const interval& b) noexcept;
  interval& operator-=(const interval& b) noexcept;
  interval& operator*=(const interval& b) noexcept;
  interval& operator/=(const interval& b) noexcept;
};

inline constexpr interval entire() noexcept { return interval::entire(); }

// ---- queries ---------------------------------------------------------------------------
inline constexpr bool contains(const interval& a, double x) noexcept { return a.lo <= x && x <= a.hi; }
inline constexpr bool intersects(const interval& a, const interval& b) noexcept {
  return a.lo <= b.hi && b.lo <= a.hi;
}
inline constexpr bool is_finite(const interval& a) noexcept {
  return a.lo > -ivl_detail::inf && a.hi < ivl_detail::inf;
}
inline constexpr bool is_entire(const interval& a) noexcept {
  return a.lo == -ivl_detail::inf && a.hi == ivl_detail::inf;
}
// An upper bound of hi - lo (inf when unbounded).
inline double width(const interval& a) noexcept { return ivl_detail::add_up(a.hi, -a.lo); }
// A point of [lo, hi] near the middle: 0 for entire, +-DBL_MAX for half-unbounded intervals.
inline double mid(const interval& a) noexcept {
  constexpr double big = std::numeric_limits<double>::max();
  if (a.lo == a.hi) return a.lo;
  if (a.lo == -ivl_detail::inf) return a.hi == ivl_detail::inf ? 0.0 : -big;
  if (a.hi == ivl_detail::inf) return big;
  double m = 0.5 * a.lo + 0.5 * a.hi;  // no overflow
  return std::clamp(m, a.lo, a.hi);
}

// ---- set operations (exact) ------------------------------------------------------------
inline constexpr interval hull(const interval& a, const interval& b) noexcept {
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}
inline constexpr interval min(const interval& a, const interval& b) noexcept {
  return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)};
}
inline constexpr interval max(const interval& a, const interval& b) noexcept {
  return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)};
}
inline constexpr interval abs(const interval& a) noexcept {
  if (a.lo >= 0) return a;
  if (a.hi <= 0) return {-a.hi, -a.lo};
  return {0.0, std::max(-a.lo, a.hi)};
}

// ---- arithmetic --------------------------------------------------------------------------
inline constexpr interval operator+(const interval& a) noexcept { return a; }
inline constexpr interval operator-(const interval& a) noexcept { return {-a.hi, -a.lo}; }

inline interval operator+(const interval& a, const interval& b) noexcept {
  return {ivl_detail::add_dn(a.lo, b.lo), ivl_detail::add_up(a.hi, b.hi)};
}
inline interval operator+(const interval& a, double b) noexcept {
  return {ivl_detail::add_dn(a.lo, b), ivl_detail::add_up(a.hi, b)};
}
inline interval operator+(double a, const interval& b) noexcept { return b + a; }

inline interval operator-(const interval& a, const interval& b) noexcept {
  return {ivl_detail::add_dn(a.lo, -b.hi), ivl_detail::add_up(a.hi, -b.lo)};
}
inline interval operator-(const interval& a, double b) noexcept { return a + (-b); }
inline interval operator-(double a, const interval& b) noexcept {
  return {ivl_detail::add_dn(a, -b.hi), ivl_detail::add_up(a, -b.lo)};
}

inline interval operator*(const interval& a, const interval& b) noexcept {
  using namespace ivl_detail;
  const double al = a.lo, ah = a.hi, bl = b.lo, bh = b.hi;
  if (al >= 0) {
    if (bl >= 0) return {mul_dn(al, bl), mul_up(ah, bh)};
    if (bh <= 0) return {mul_dn(ah, bl), mul_up(al, bh)};
    return {mul_dn(ah, bl), mul_up(ah, bh)};
  }
  if (ah <= 0) {
    if (bl >= 0) return {mul_dn(al, bh), mul_up(ah, bl)};
    if (bh <= 0) return {mul_dn(ah, bh), mul_up(al, bl)};
    return {mul_dn(al, bh), mul_up(al, bl)};
  }
  if (bl >= 0) return {mul_dn(al, bh), mul_up(ah, bh)};
  if (bh <= 0) return {mul_dn(ah, bl), mul_up(al, bl)};
  return {std::min(mul_dn(al, bh), mul_dn(ah, bl)), std::max(mul_up(al, bl), mul_up(ah, bh))};
}
inline interval operator*(const interval& a, double s) noexcept {
  using namespace ivl_detail;
  if (s >= 0) return {mul_dn(a.lo, s), mul_up(a.hi, s)};
  if (s < 0) return {mul_dn(a.hi, s), mul_up(a.lo, s)};
  return entire();  // NaN scale
}
inline interval operator*(double s, const interval& a) noexcept { return a * s; }

// Division by an interval that contains 0 (including [0, 0]) is entire().
inline interval operator/(const interval& a, const interval& b) noexcept {
  using namespace ivl_detail;
  const double al = a.lo, ah = a.hi, bl = b.lo, bh = b.hi;
  if (bl > 0) {
    if (al >= 0) return {div_dn(al, bh), div_up(ah, bl)};
    if (ah <= 0) return {div_dn(al, bl), div_up(ah, bh)};
    return {div_dn(al, bl), div_up(ah, bl)};
  }
  if (bh < 0) {
    if (al >= 0) return {div_dn(ah, bh), div_up(al, bl)};
    if (ah <= 0) return {div_dn(ah, bl), div_up(al, bh)};
    return {div_dn(ah, bh), div_up(al, bh)};
  }
  return entire();
}
inline interval operator/(const interval& a, double s) noexcept {
  using namespace ivl_detail;
  if (s > 0) return {div_dn(a.lo, s), div_up(a.hi, s)};
  if (s < 0) return {div_dn(a.hi, s), div_up(a.lo, s)};
  return entire();
}
inline interval operator/(double a, const interval& b) noexcept { return interval(a) / b; }

inline interval& interval::operator+=(const interval& b) noexcept { return *this = *this + b; }
inline interval& interval::operator-=(const interval& b) noexcept { return *this = *this - b; }
inline interval& interval::operator*=(const interval& b) noexcept { return *this = *this * b; }
inline interval& interval::operator/=(const interval& b) noexcept { return *this = *this / b; }

// ---- elementary functions ----------------------------------------------------------------
// x^2, tight: [0, max] when x contains 0.
inline interval sqr(const interval& a) noexcept {
  using namespace ivl_detail;
  // (max with 0: an underflowing square rounds down to -denorm_min)
  if (a.lo >= 0) return {std::max(0.0, mul_dn(a.lo, a.lo)), mul_up(a.hi, a.hi)};
  if (a.hi <= 0) return {std::max(0.0, mul_dn(a.hi, a.hi)), mul_up(a.lo, a.lo)};
  return {0.0, mul_up(std::max(-a.lo, a.hi), std::max(-a.lo, a.hi))};
}

// sqrt over the part of x that is >= 0: sqrt([-1, 4]) = [0, 2]; entirely negative -> [0, 0]
// (callers check positivity first).
inline interval sqrt(const interval& a) noexcept {
  return {ivl_detail::sqrt_dn(a.lo), ivl_detail::sqrt_up(a.hi)};
}

// x^k over the part of x that is >= 0 (x is clamped to >= 0; 0^k = 0 for k > 0).
// k == 0 gives [1, 1] for any x. k > 0: increasing. k < 0 (allowed, for the derivatives of
// x^k): decreasing, [hi^k, +inf] when x reaches 0, entire() when x has no positive part.
inline interval pow(const interval& a, double k) noexcept {
  using namespace ivl_detail;
  if (k == 0) return {1.0, 1.0};
  const double lo = std::max(a.lo, 0.0), hi = std::max(a.hi, 0.0);
  if (k == 1) return {lo, hi};
  if (k == 2) return sqr(interval(lo, hi));
  if (k == 0.5) return sqrt(interval(lo, hi));
  if (k > 0) return {pow_dn(lo, k), pow_up(hi, k)};
  if (k < 0) {
    if (hi <= 0) return entire();
    return {pow_dn(hi, k), lo <= 0 ? inf : pow_up(lo, k)};
  }
  return entire();  // NaN exponent
}

// ---- scalar companions for code templated on T = double / interval / jet ------------------
// Unqualified sqrt(x) inside namespace epsray would otherwise find only the interval and jet
// overloads (which hide ::sqrt) and turn a double into an interval. These forward to the std
// functions with their usual types and semantics (no interval clamping).
template <class F>
  requires std::is_floating_point_v<F>
inline constexpr F sqr(F x) noexcept {
  return x * x;
}
template <class F>
  requires std::is_floating_point_v<F>
inline F sqrt(F x) noexcept {
  return std::sqrt(x);
}
template <class F>
  requires std::is_floating_point_v<F>
inline auto pow(F x, double k) noexcept {
  return std::pow(x, k);
}
template <class F>
  requires std::is_floating_point_v<F>
inline F abs(F x) noexcept {
  return std::fabs(x);
}

}  // namespace epsray
