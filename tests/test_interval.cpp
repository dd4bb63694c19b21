// interp/interval.h, interp/jet.h, interp/vec3t.h: enclosures must be CONSERVATIVE.
//  (a) random intervals and random points inside them: the exact result at the points lies in
//      the interval result (products, sums exact in binary128; quotients and square roots
//      checked by exact back-multiplication; pow against powl);
//  (b) jet<double> reproduces analytic first and second derivatives;
//  (c) jet<interval> over a box encloses the analytic value, first and second derivative at
//      many points of the box (compound functions and a ray-sphere intersection distance);
//  (d) edge cases never give NaN.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>
#include <random>
#include <vector>

#include "interp/interval.h"
#include "interp/jet.h"
#include "interp/vec3t.h"

namespace epsray {

void PrintTo(const interval& a, std::ostream* os) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.17g, %.17g]", a.lo, a.hi);
  *os << buf;
}

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double big = std::numeric_limits<double>::max();

#if defined(__SIZEOF_FLOAT128__)
using wide = __float128;  // holds any product of two doubles exactly
#else
using wide = long double;  // weaker reference: products rounded to 64 bits (monotone, still valid)
#endif

bool sane(const interval& r) { return !std::isnan(r.lo) && !std::isnan(r.hi) && r.lo <= r.hi; }
template <class T>
bool sane(const jet<T>& j) {
  return sane(j.v) && sane(j.d) && sane(j.dd);
}
template <class T>
bool sane(const vec3t<T>& u) {
  return sane(u.x) && sane(u.y) && sane(u.z);
}

::testing::AssertionResult encloses(const interval& r, wide x) {
  if (!sane(r)) return ::testing::AssertionFailure() << "bad interval " << ::testing::PrintToString(r);
  if (wide(r.lo) <= x && x <= wide(r.hi)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << ::testing::PrintToString(r) << " misses "
                                       << static_cast<double>(x) << " (as double)";
}

// ---- random inputs ---------------------------------------------------------------------------
struct gen {
  std::mt19937_64 rng{12345};
  double uniform() { return std::uniform_real_distribution<double>(0.0, 1.0)(rng); }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }

  // Doubles of all kinds: moderate, extreme, subnormal, short significands (exact paths), 0.
  double number() {
    double sign = pick(2) ? 1.0 : -1.0;
    switch (pick(10)) {
      case 0: return 0.0;
      case 1: return sign * (1 + pick(16)) * std::ldexp(1.0, pick(9) - 4);  // short: 3, 0.75, 12
      case 2: {  // anywhere in the range, subnormals included
        std::uint64_t u = rng() & 0x7fefffffffffffffULL;
        return sign * std::bit_cast<double>(u);
      }
      case 3: return sign * std::ldexp(uniform() + 0.5, pick(200) - 100);
      default: return sign * std::ldexp(uniform() + 0.5, pick(40) - 20);
    }
  }
  interval box() {
    switch (pick(12)) {
      case 0: {
        double x = number();
        return {x, x};
      }
      case 1: return {0.0, std::fabs(number())};
      case 2: return {-std::fabs(number()), 0.0};
      case 3: return {-std::fabs(number()), std::fabs(number())};
      case 4: return {number(), inf};
      case 5: return {-inf, number()};
      case 6: return pick(4) ? interval(-std::fabs(number()), inf) : entire();
      default: {
        double a = number(), b = pick(3) ? number() : a * (1 + 1e-6 * uniform());
        return {std::min(a, b), std::max(a, b)};
      }
    }
  }
  // Real points of a: the finite ends, their neighbours, 0, and random interior points.
  std::vector<double> points(const interval& a) {
    double lo = a.lo == -inf ? -big : a.lo, hi = a.hi == inf ? big : a.hi;
    std::vector<double> p{lo, hi};
    if (lo < hi) p.push_back(ivl_detail::next_up(lo)), p.push_back(ivl_detail::next_down(hi));
    if (lo <= 0 && 0 <= hi) p.push_back(0.0);
    for (int i = 0; i < 3; ++i) {
      double u = uniform();
      p.push_back(std::clamp(lo * (1 - u) + hi * u, lo, hi));
    }
    if (a.lo == -inf) p.push_back(-1e300);
    if (a.hi == inf) p.push_back(1e300);
    return p;
  }
};

// Exact tests "l <= x / y" and "x / y <= h" (y != 0) by back-multiplication.
bool le_quot(double l, double x, double y) {
  if (l == -inf) return true;
  if (l == inf) return false;
  return y > 0 ? wide(l) * y <= wide(x) : wide(l) * y >= wide(x);
}
bool ge_quot(double h, double x, double y) {
  if (h == inf) return true;
  if (h == -inf) return false;
  return y > 0 ? wide(h) * y >= wide(x) : wide(h) * y <= wide(x);
}
// "l <= sqrt(x)" and "sqrt(x) <= h" for x >= 0, exactly.
bool le_sqrt(double l, double x) { return l <= 0 || (l < inf && wide(l) * l <= wide(x)); }
bool ge_sqrt(double h, double x) { return h == inf || (h >= 0 && wide(h) * h >= wide(x)); }

constexpr int kBoxes = 6000;

// ---- (a) random enclosure tests ---------------------------------------------------------------
TEST(Interval, NextUpDownMatchStdNextafter) {
  const double v[] = {0.0, -0.0, DBL_TRUE_MIN, -DBL_TRUE_MIN, DBL_MIN, -DBL_MIN, big, -big, inf, -inf,
                      1.0, -1.0, 0.1, -3.5e300, 2.2e-310};
  for (double x : v) {
    EXPECT_EQ(ivl_detail::next_up(x), std::nextafter(x, inf)) << x;
    EXPECT_EQ(ivl_detail::next_down(x), std::nextafter(x, -inf)) << x;
  }
  gen g;
  for (int i = 0; i < 100000; ++i) {
    double x = g.number();
    ASSERT_EQ(ivl_detail::next_up(x), std::nextafter(x, inf)) << x;
    ASSERT_EQ(ivl_detail::next_down(x), std::nextafter(x, -inf)) << x;
  }
}

TEST(Interval, RandomArithmeticEnclosesPointResults) {
  gen g;
  long checks = 0;
  for (int n = 0; n < kBoxes; ++n) {
    interval a = g.box(), b = g.box();
    double s = g.number();
    auto pa = g.points(a), pb = g.points(b);
    interval add = a + b, sub = a - b, mul = a * b, div = a / b;
    interval adds = a + s, sadd = s + a, subs = a - s, ssub = s - a, muls = a * s, smul = s * a;
    interval divs = a / s, sdiv = s / b;
    interval acc = a;
    acc += b;
    EXPECT_EQ(acc, add);
    acc = a, acc -= b;
    EXPECT_EQ(acc, sub);
    acc = a, acc *= b;
    EXPECT_EQ(acc, mul);
    acc = a, acc /= b;
    EXPECT_EQ(acc, div);
    const bool b0 = contains(b, 0.0);
    if (b0) {
      EXPECT_TRUE(is_entire(div)) << ::testing::PrintToString(b);
      EXPECT_TRUE(is_entire(sdiv));
    }
    if (s == 0) {
      EXPECT_TRUE(is_entire(divs));
    }
    for (double x : pa) {
      ASSERT_TRUE(encloses(adds, wide(x) + s)) << x << " + " << s;
      ASSERT_TRUE(encloses(sadd, wide(s) + x));
      ASSERT_TRUE(encloses(subs, wide(x) - s)) << x << " - " << s;
      ASSERT_TRUE(encloses(ssub, wide(s) - x)) << s << " - " << x;
      ASSERT_TRUE(encloses(muls, wide(x) * s)) << x << " * " << s;
      ASSERT_TRUE(encloses(smul, wide(s) * x));
      ASSERT_TRUE(encloses(-a, -wide(x)));
      ASSERT_TRUE(encloses(abs(a), x < 0 ? -wide(x) : wide(x)));
      ASSERT_TRUE(encloses(sqr(a), wide(x) * x)) << x;
      ASSERT_TRUE(encloses(hull(a, b), x));
      if (s != 0) {
        ASSERT_TRUE(sane(divs));
        ASSERT_TRUE(le_quot(divs.lo, x, s) && ge_quot(divs.hi, x, s)) << x << " / " << s;
      }
      for (double y : pb) {
        ASSERT_TRUE(encloses(add, wide(x) + y)) << x << " + " << y;
        ASSERT_TRUE(encloses(sub, wide(x) - y)) << x << " - " << y;
        ASSERT_TRUE(encloses(mul, wide(x) * y)) << x << " * " << y;
        ASSERT_TRUE(encloses(min(a, b), std::min(x, y)));
        ASSERT_TRUE(encloses(max(a, b), std::max(x, y)));
        if (!b0) {
          ASSERT_TRUE(sane(div));
          ASSERT_TRUE(le_quot(div.lo, x, y) && ge_quot(div.hi, x, y))
              << x << " / " << y << " in " << ::testing::PrintToString(div);
        }
        if (y != 0 && b0) {
          ASSERT_TRUE(sane(sdiv));
        }
        if (y != 0 && !b0) {
          ASSERT_TRUE(le_quot(sdiv.lo, s, y) && ge_quot(sdiv.hi, s, y)) << s << " / " << y;
        }
        checks += 9;
      }
      checks += 10;
    }
    EXPECT_TRUE(intersects(a, b) == (a.lo <= b.hi && b.lo <= a.hi));
  }
  std::printf("[          ] %ld point checks\n", checks);
}

TEST(Interval, RandomSqrtPowEnclosePointResults) {
  gen g;
  const double ks[] = {0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 7.0, 10.0, 0.3, 64.0, -0.5, -1.5};
  long checks = 0;
  for (int n = 0; n < kBoxes; ++n) {
    interval a = g.box();
    auto pa = g.points(a);
    interval r = sqrt(a);
    ASSERT_TRUE(sane(r));
    ASSERT_GE(r.lo, 0.0);
    for (double x : pa) {
      double c = std::max(x, 0.0);  // the clamped domain
      ASSERT_TRUE(le_sqrt(r.lo, c) && ge_sqrt(r.hi, c)) << "sqrt " << x << " " << ::testing::PrintToString(r);
      ++checks;
    }
    for (double k : ks) {
      interval p = pow(a, k);
      ASSERT_TRUE(sane(p)) << k;
      if (k > 0) {
        ASSERT_GE(p.lo, 0.0);
      }
      for (double x : pa) {
        long double c = std::max(x, 0.0);
        if (k < 0 && c == 0) continue;  // unbounded there
        long double ref = k == 0 ? 1.0L : powl(c, static_cast<long double>(k));
        ASSERT_TRUE((long double)p.lo <= ref && ref <= (long double)p.hi)
            << "pow(" << x << ", " << k << ") = " << (double)ref << " not in " << ::testing::PrintToString(p);
        ++checks;
      }
    }
  }
  std::printf("[          ] %ld point checks\n", checks);
}

// Squares of short significands: sqrt is exact when s has at most 26 bits, and must not claim
// exactness for 27 or more bits, where fl(s * s) may round.
TEST(Interval, SqrtOfSquares) {
  gen g;
  for (int n = 0; n < 200000; ++n) {
    int bits = 20 + g.pick(14);
    double m = static_cast<double>((g.rng() >> (64 - bits)) | (std::uint64_t(1) << (bits - 1)));
    double s = std::ldexp(m, g.pick(200) - 100 - bits);
    double x = s * s;  // rounded once bits > 26
    interval r = sqrt(interval(x));
    ASSERT_TRUE(le_sqrt(r.lo, x) && ge_sqrt(r.hi, x)) << s << " " << bits;
    if (bits <= 26) {
      ASSERT_EQ(r, interval(s));
    }
    interval p = interval(s) * s;  // the product: exact only when it fits
    ASSERT_TRUE(encloses(p, wide(s) * s));
  }
}

// Short significands (results that look exact) landing near the underflow and overflow
// thresholds, where rounding does happen.
TEST(Interval, ShortSignificandsAtTheRangeLimits) {
  gen g;
  auto short_number = [&](int lo_exp, int hi_exp) {
    double m = static_cast<double>(1 + 2 * g.pick(8));  // 1, 3, ..., 15
    double x = std::ldexp(m, lo_exp + g.pick(hi_exp - lo_exp + 1));
    return g.pick(2) ? x : -x;
  };
  for (int n = 0; n < 200000; ++n) {
    double x = short_number(-1080, -1000), y = short_number(-60, 10);
    if (g.pick(2)) x = short_number(960, 1019), y = short_number(-10, 70);
    if (x == 0 || y == 0) continue;
    interval p = interval(x) * y, q = interval(x) / y, r = interval(y) / x;
    ASSERT_TRUE(encloses(p, wide(x) * y)) << x << " * " << y;
    ASSERT_TRUE(le_quot(q.lo, x, y) && ge_quot(q.hi, x, y)) << x << " / " << y;
    ASSERT_TRUE(le_quot(r.lo, y, x) && ge_quot(r.hi, y, x)) << y << " / " << x;
  }
}

// Tightness: inexact results move exactly one ulp out; zeros, exact squares under sqrt and the
// set operations are exact, so signs survive.
interval one_ulp_out(double lo, double hi) { return {std::nextafter(lo, -inf), std::nextafter(hi, inf)}; }

TEST(Interval, OneUlpOutExceptExactCases) {
  EXPECT_EQ(interval(1.0) + interval(2.0), one_ulp_out(3.0, 3.0));
  EXPECT_EQ(interval(1.0, 2.0) - interval(1.0, 2.0), one_ulp_out(-1.0, 1.0));
  EXPECT_EQ(interval(1.0, 2.0) * 2.0, one_ulp_out(2.0, 4.0));
  EXPECT_EQ(interval(-3.0, 2.0) * interval(0.5, 4.0), one_ulp_out(-12.0, 8.0));
  EXPECT_EQ(interval(3.0, 6.0) / interval(1.5, 3.0), one_ulp_out(1.0, 4.0));
  EXPECT_EQ(sqr(interval(-3.0, -2.0)), one_ulp_out(4.0, 9.0));
  EXPECT_EQ(interval(1.0) / 3.0, one_ulp_out(1.0 / 3.0, 1.0 / 3.0));
  EXPECT_EQ(sqrt(interval(2.0)), one_ulp_out(std::sqrt(2.0), std::sqrt(2.0)));
  interval t = interval(1.0) / 3.0, r2 = sqrt(interval(2.0));
  EXPECT_TRUE(le_quot(t.lo, 1.0, 3.0) && ge_quot(t.hi, 1.0, 3.0));
  EXPECT_TRUE(le_sqrt(r2.lo, 2.0) && ge_sqrt(r2.hi, 2.0));
  EXPECT_TRUE(encloses(interval(1.0) + 1e-30, wide(1.0) + wide(1e-30)));
  EXPECT_TRUE(encloses(interval(1.0) - 1e-30, wide(1.0) - wide(1e-30)));

  // Exact: zero operands and zero sums (signs survive), exact squares under sqrt, set operations.
  EXPECT_EQ(interval(0.0, 1.0) * 2.0, interval(0.0, std::nextafter(2.0, inf)));
  EXPECT_EQ(interval(0.0, 1.0) + interval(0.0), interval(0.0, 1.0));
  EXPECT_EQ(interval(1.5) - interval(1.5), interval(0.0));
  EXPECT_EQ(interval(0.0, 3.0) / interval(2.0, 4.0), interval(0.0, std::nextafter(1.5, inf)));
  EXPECT_EQ(sqr(interval(-2.0, 3.0)), interval(0.0, std::nextafter(9.0, inf)));
  EXPECT_EQ(sqrt(interval(-1.0, 4.0)), interval(0.0, 2.0));
  EXPECT_EQ(sqrt(interval(-3.0, -1.0)), interval(0.0, 0.0));
  EXPECT_EQ(sqrt(interval(0.25, 16.0)), interval(0.5, 4.0));
  EXPECT_EQ(pow(interval(0.0, 4.0), 0.5), interval(0.0, 2.0));
  EXPECT_EQ(pow(interval(-5.0, 7.0), 0.0), interval(1.0, 1.0));
  EXPECT_EQ(pow(interval(-2.0, -1.0), 3.0), interval(0.0, 0.0));
  EXPECT_EQ(pow(interval(-1.0, 2.0), 3.0).lo, 0.0);
  EXPECT_EQ(pow(interval(-1.0, 1.0), 3.5), interval(0.0, 1.0));
  EXPECT_EQ(abs(interval(-3.0, 2.0)), interval(0.0, 3.0));
  EXPECT_EQ(-interval(-3.0, 2.0), interval(-2.0, 3.0));
  EXPECT_EQ(hull(interval(1.0, 2.0), interval(5.0, 6.0)), interval(1.0, 6.0));
  EXPECT_EQ(min(interval(1.0, 7.0), interval(5.0, 6.0)), interval(1.0, 6.0));
  EXPECT_EQ(max(interval(1.0, 7.0), interval(5.0, 6.0)), interval(5.0, 7.0));

  EXPECT_EQ(mid(interval(1.0, 3.0)), 2.0);
  EXPECT_EQ(mid(entire()), 0.0);
  EXPECT_EQ(mid(interval(-inf, 3.0)), -big);
  EXPECT_GE(width(interval(1.0, 3.0)), 2.0);
  EXPECT_LE(width(interval(1.0, 3.0)), std::nextafter(2.0, inf));
  EXPECT_EQ(width(interval(-inf, 3.0)), inf);
  EXPECT_TRUE(is_finite(interval(1.0, 3.0)));
  EXPECT_FALSE(is_finite(interval(1.0, inf)));
  EXPECT_TRUE(contains(interval(1.0, 3.0), 3.0));
  EXPECT_FALSE(contains(interval(1.0, 3.0), 3.5));
  EXPECT_TRUE(intersects(interval(1.0, 3.0), interval(3.0, 4.0)));
  EXPECT_FALSE(intersects(interval(1.0, 3.0), interval(3.5, 4.0)));
  EXPECT_EQ(interval::entire(), entire());
  EXPECT_EQ(interval(), interval(0.0));
}

TEST(Interval, OverflowAndUnderflowStayConservative) {
  interval o = interval(big) * 2.0;  // 2 * DBL_MAX is a finite real above DBL_MAX
  EXPECT_EQ(o.lo, big);
  EXPECT_EQ(o.hi, inf);
  interval s = interval(big) + interval(big);
  EXPECT_EQ(s.lo, big);
  EXPECT_EQ(s.hi, inf);
  interval u = interval(1e-300) * interval(1e-300);  // 1e-600 underflows to 0
  EXPECT_LE(u.lo, 0.0);
  EXPECT_GT(u.hi, 0.0);
  interval q = interval(DBL_TRUE_MIN) / 4.0;
  EXPECT_LE(q.lo, 0.0);
  EXPECT_GT(q.hi, 0.0);
}

// ---- (d) edge cases: no NaN ---------------------------------------------------------------------
TEST(Interval, EdgeCasesNeverNaN) {
  EXPECT_EQ(interval(0.0) * entire(), interval(0.0));  // 0 * inf = 0
  EXPECT_EQ(interval(0.0, 1.0) * interval(1.0, inf), interval(0.0, inf));
  EXPECT_EQ(interval(-inf, 0.0) * interval(0.0, 0.0), interval(0.0));
  EXPECT_EQ(interval(0.0) * inf, interval(0.0));
  EXPECT_TRUE(is_entire(entire() - entire()));
  EXPECT_TRUE(is_entire(interval(inf) - interval(inf)));  // inf - inf in a bound
  EXPECT_TRUE(is_entire(interval(inf) + interval(-inf)));
  EXPECT_TRUE(is_entire(interval(1.0, 2.0) / interval(0.0)));
  EXPECT_TRUE(is_entire(interval(0.0) / interval(0.0)));
  EXPECT_TRUE(is_entire(interval(1.0, 2.0) / interval(0.0, 1.0)));
  EXPECT_TRUE(is_entire(interval(1.0, 2.0) / 0.0));
  EXPECT_TRUE(is_entire(1.0 / interval(-1.0, 1.0)));
  EXPECT_TRUE(sane(interval(inf) / interval(inf)));
  EXPECT_TRUE(sane(interval(1.0, inf) / interval(1.0, inf)));
  interval d = interval(1.0, 2.0) / interval(1.0, inf);  // (0, 2]: the lower end stays 0
  EXPECT_EQ(d.lo, 0.0);
  EXPECT_GE(d.hi, 2.0);
  EXPECT_EQ(sqrt(interval(-4.0, -1.0)), interval(0.0));
  EXPECT_EQ(sqrt(entire()), interval(0.0, inf));
  EXPECT_EQ(pow(interval(0.0), 0.5), interval(0.0));
  EXPECT_EQ(pow(interval(0.0), 1.5), interval(0.0));
  EXPECT_EQ(pow(interval(0.0), 0.0), interval(1.0));
  EXPECT_EQ(pow(entire(), 3.5), interval(0.0, inf));
  EXPECT_TRUE(sane(pow(interval(0.0, 2.0), -0.5)));
  EXPECT_TRUE(is_entire(interval(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_TRUE(sane(mid(entire()) + interval(0.0)));
  EXPECT_TRUE(sane(abs(entire())));
  EXPECT_TRUE(sane(sqr(entire())));

  // Jets: singular points give unbounded (entire) components, never NaN.
  auto x0 = jet_variable(interval(0.0, 1.0));
  auto s = sqrt(x0);
  EXPECT_TRUE(sane(s));
  EXPECT_TRUE(is_entire(s.d) && is_entire(s.dd));
  EXPECT_EQ(s.v, interval(0.0, 1.0));
  auto p = pow(x0, 0.5);
  EXPECT_TRUE(sane(p) && is_entire(p.d) && is_entire(p.dd));
  auto p15 = pow(x0, 1.5);
  EXPECT_TRUE(sane(p15) && is_finite(p15.d) && is_entire(p15.dd));
  auto q = jet_constant(interval(1.0)) / jet_variable(interval(0.0));
  EXPECT_TRUE(sane(q));
  auto q2 = 1.0 / (x0 - 0.5);
  EXPECT_TRUE(sane(q2) && is_entire(q2.v));
  auto m = max0(x0 - 0.5);
  EXPECT_TRUE(sane(m) && is_entire(m.d) && is_entire(m.dd));
  EXPECT_EQ(m.v, interval(0.0, std::nextafter(0.5, inf)));  // 1 - 0.5 is widened
  auto z = jet_variable(interval(0.0)) * jet<interval>{entire(), entire(), entire()};
  EXPECT_TRUE(sane(z));
  EXPECT_TRUE(sane(sqrt(jet_variable(interval(-2.0, -1.0)))));
  EXPECT_TRUE(sane(pow(jet_variable(interval(-2.0, -1.0)), 0.5)));
  EXPECT_TRUE(sane(pow(jet_variable(interval(-2.0, 3.0)), 2.5)));
  EXPECT_TRUE(sane(normalize(vec3t<jet<interval>>{x0, x0, x0})));
}

// ---- analytic references (sympy) ------------------------------------------------------------------
struct ref3 {
  long double v, d, dd;
};
using std::pow;
using std::sqrt;

// f1 = sqrt(1 + x^2) / (2 + x)
template <class T>
T f1(const T& x) {
  return sqrt(1.0 + sqr(x)) / (2.0 + x);
}
ref3 f1_ref(long double x) {
  return {sqrt(pow(x, 2) + 1) / (x + 2), (2 * x - 1) / (sqrt(pow(x, 2) + 1) * (pow(x, 2) + 4 * x + 4)),
          (-2 * x * (x + 2) * (pow(x, 2) + 1) + pow(x + 2, 2) + 2 * pow(pow(x, 2) + 1, 2)) /
              (pow(x + 2, 3) * pow(pow(x, 2) + 1, 3.0L / 2.0L))};
}
// f2 = (x^2 + 1)^3.5
template <class T>
T f2(const T& x) {
  return pow(sqr(x) + 1.0, 3.5);
}
ref3 f2_ref(long double x) {
  return {pow(pow(x, 2) + 1, 7.0L / 2.0L), 7 * x * pow(pow(x, 2) + 1, 5.0L / 2.0L),
          pow(pow(x, 2) + 1, 3.0L / 2.0L) * (42 * pow(x, 2) + 7)};
}
// f3 = normalize((x, 1, 2)).y
template <class T>
T f3(const T& x) {
  return normalize(vec3t<T>{x, T{1.0}, T{2.0}}).y;
}
ref3 f3_ref(long double x) {
  return {pow(pow(x, 2) + 5, -1.0L / 2.0L), -x / pow(pow(x, 2) + 5, 3.0L / 2.0L),
          (2 * pow(x, 2) - 5) / pow(pow(x, 2) + 5, 5.0L / 2.0L)};
}
// f4: distance along the line of origin (x, 0, -5), direction normalize(0.1 x, 0.05, 1) to the
// unit sphere at the origin (first hit): t = -b - sqrt(b^2 - c), b = o.d, c = o.o - 1.
template <class T>
T ray_t(const T& x) {
  vec3t<T> o{x, T{0.0}, T{-5.0}};
  vec3t<T> d = normalize(vec3t<T>{0.1 * x, T{0.05}, T{1.0}});
  T b = dot(o, d);
  T c = length_squared(o) - 1.0;
  return -b - sqrt(sqr(b) - c);
}
ref3 ray_t_ref(long double x) {
  const long double a = 0.1, e = 0.05;  // the doubles the formula uses
  long double D = -(pow(x, 2) + 24) * (pow(a, 2) * pow(x, 2) + pow(e, 2) + 1) + pow(a * pow(x, 2) - 5, 2);
  long double L2 = pow(a, 2) * pow(x, 2) + pow(e, 2) + 1;
  long double v = (-a * pow(x, 2) - sqrt(D) + 5) / sqrt(L2);
  long double d = x *
                  (pow(a, 2) * pow(a * pow(x, 2) - 5, 2) + pow(a, 2) * (a * pow(x, 2) - 5) * sqrt(D) -
                   2 * a * (a * pow(x, 2) - 5) * L2 - 2 * a * sqrt(D) * L2 + pow(L2, 2)) /
                  (sqrt(D) * pow(L2, 3.0L / 2.0L));
  long double dd =
      (3 * pow(a, 4) * pow(x, 2) * (-a * pow(x, 2) + 5) * pow(D, 2) +
       5 * pow(a, 2) * (a * pow(x, 2) - 1) * pow(D, 2) * L2 - 2 * a * pow(D, 2) * pow(L2, 2) +
       pow(x, 2) * sqrt(D) *
           pow(pow(a, 2) * pow(a * pow(x, 2) - 5, 2) - 2 * a * (a * pow(x, 2) - 5) * L2 + pow(L2, 2), 2) +
       pow(D, 3.0L / 2.0L) *
           (-4 * pow(a, 4) * pow(x, 2) * pow(a * pow(x, 2) - 5, 2) +
            pow(a, 2) * (a * pow(x, 2) - 5) * (9 * a * pow(x, 2) - 5) * L2 +
            2 * a * (-3 * a * pow(x, 2) + 5) * pow(L2, 2) + pow(L2, 3))) /
      (pow(D, 2) * pow(L2, 5.0L / 2.0L));
  return {v, d, dd};
}
// f5: a highlight lobe max(0, 1 - x^2)^8, written the way shading code writes it.
template <class T>
T f5(const T& x) {
  return pow(max0(1.0 - sqr(x)), 8.0);
}
ref3 f5_ref(long double x) {
  long double u = 1 - x * x;
  if (u <= 0) return {0, 0, 0};
  return {pow(u, 8), -16 * x * pow(u, 7), -16 * pow(u, 7) + 224 * x * x * pow(u, 6)};
}
// f6: the same lobe through pow's own clamping (max(0, f)^k), which keeps f'' bounded at the
// edge of the lobe for k >= 2.
template <class T>
T f6(const T& x) {
  return pow(1.0 - sqr(x), 8.0);
}
// f7: quotients with scalars on both sides and mixed jet/T products.
template <class T>
T f7(const T& x) {
  T y = 3.0 / (1.0 + sqr(x)) - x / 4.0;
  return y * y * x - 2.0 * x + (x - 0.5) * (1.0 - x);
}
ref3 f7_ref(long double x) {
  long double g = 1 + x * x, y = 3 / g - x / 4;
  long double dy = -6 * x / (g * g) - 0.25L;
  long double ddy = -6 / (g * g) + 24 * x * x / (g * g * g);
  // y^2 x - 2x + (x - 0.5)(1 - x) = y^2 x - x^2 - 0.5 + 0.5 x
  return {y * y * x - 2 * x + (x - 0.5L) * (1 - x), 2 * y * dy * x + y * y - 2 + 1.5L - 2 * x,
          2 * (dy * dy + y * ddy) * x + 4 * y * dy - 2};
}

// f8: max(0, x - 0.3)^2, whose f'' jumps from 0 to 2 (pow's clamp, k == 2).
template <class T>
T f8(const T& x) {
  return pow(x - 0.3, 2.0);
}
ref3 f8_ref(long double x) {
  long double u = x - 0.3;
  if (u < 0) return {0, 0, 0};
  return {u * u, 2 * u, 2};
}

struct fn_case {
  const char* name;
  std::function<jet<double>(jet<double>)> fd;
  std::function<jet<long double>(jet<long double>)> fl;
  std::function<jet<interval>(jet<interval>)> fi;
  ref3 (*ref)(long double);
  double lo, hi;  // where boxes are drawn
};
#define EPSRAY_CASE(f, ref, lo, hi) \
  fn_case { #f, f<jet<double>>, f<jet<long double>>, f<jet<interval>>, ref, lo, hi }
std::vector<fn_case> cases() {
  return {EPSRAY_CASE(f1, f1_ref, -1.5, 3.0),     EPSRAY_CASE(f2, f2_ref, -3.0, 3.0),
          EPSRAY_CASE(f3, f3_ref, -5.0, 5.0),     EPSRAY_CASE(ray_t, ray_t_ref, -0.5, 0.5),
          EPSRAY_CASE(f5, f5_ref, -1.5, 1.5),     EPSRAY_CASE(f6, f5_ref, -1.5, 1.5),
          EPSRAY_CASE(f7, f7_ref, -2.0, 2.0),     EPSRAY_CASE(f8, f8_ref, -0.5, 1.0)};
}

bool near(long double a, long double b, long double tol) {
  return std::fabs(a - b) <= tol * std::max(1.0L, std::fabs(b));
}

// ---- (b) jet<double> derivatives ---------------------------------------------------------------
TEST(Jet, DoubleMatchesAnalyticDerivatives) {
  gen g;
  for (const auto& c : cases()) {
    for (int i = 0; i < 2000; ++i) {
      double x = c.lo + (c.hi - c.lo) * g.uniform();
      if (std::fabs(std::fabs(x) - 1) < 1e-3 && (c.ref == f5_ref)) continue;  // lobe edge
      if (std::fabs(x - 0.3) < 1e-3 && (c.ref == f8_ref)) continue;
      ref3 r = c.ref(x);
      jet<double> j = c.fd(jet_variable(x));
      ASSERT_TRUE(near(j.v, r.v, 1e-9) && near(j.d, r.d, 1e-9) && near(j.dd, r.dd, 1e-9))
          << c.name << "(" << x << "): jet " << j.v << " " << j.d << " " << j.dd << " analytic "
          << (double)r.v << " " << (double)r.d << " " << (double)r.dd;
      jet<long double> jl = c.fl(jet_variable<long double>(x));
      ASSERT_TRUE(near(jl.v, r.v, 1e-12) && near(jl.d, r.d, 1e-12) && near(jl.dd, r.dd, 1e-12)) << c.name;
    }
  }
}

TEST(Jet, DoubleRulesOnSmallCases) {
  // (x^2+1)^3.5 at x = 1: 2^3.5, 7 * 2^2.5, 7 * 2^1.5 * 7
  jet<double> p = pow(sqr(jet_variable(1.0)) + 1.0, 3.5);
  EXPECT_NEAR(p.v, std::pow(2.0, 3.5), 1e-12);
  EXPECT_NEAR(p.d, 7 * std::pow(2.0, 2.5), 1e-12);
  EXPECT_NEAR(p.dd, 49 * std::pow(2.0, 1.5), 1e-12);
  // normalize((x, 1, 2)).y at x = 2: 1/3, -2/27, 3/243
  jet<double> y = normalize(vec3t<jet<double>>{jet_variable(2.0), {1.0}, {2.0}}).y;
  EXPECT_NEAR(y.v, 1.0 / 3, 1e-15);
  EXPECT_NEAR(y.d, -2.0 / 27, 1e-15);
  EXPECT_NEAR(y.dd, 3.0 / 243, 1e-15);
  // max0 and pow's clamping at points
  EXPECT_EQ(max0(jet_variable(-1.0)).d, 0.0);
  EXPECT_EQ(max0(jet_variable(2.0)).d, 1.0);
  EXPECT_EQ(pow(jet_variable(-1.0), 3.0).dd, 0.0);
  EXPECT_TRUE(std::isnan(sqrt(jet_variable(0.0)).d));  // a point at sqrt's singularity
  // jet / T, T / jet, compound assignment
  jet<double> a = jet_variable(2.0);
  jet<double> b = 1.0 / a;  // 1/x: -1/x^2, 2/x^3
  EXPECT_DOUBLE_EQ(b.d, -0.25);
  EXPECT_DOUBLE_EQ(b.dd, 0.25);
  a *= a;
  a += 1.0;
  a /= 2.0;
  a -= jet_variable(2.0);  // (x^2 + 1)/2 - x
  EXPECT_DOUBLE_EQ(a.v, 0.5);
  EXPECT_DOUBLE_EQ(a.d, 1.0);
  EXPECT_DOUBLE_EQ(a.dd, 1.0);
  // vec3t
  vec3t<double> u{1, 2, 3}, v{4, 5, 6};
  EXPECT_EQ(dot(u, v), 32.0);
  vec3t<double> w = cross(u, v);
  EXPECT_EQ(w.x, -3.0);
  EXPECT_EQ(w.y, 6.0);
  EXPECT_EQ(w[2], -3.0);
  EXPECT_EQ(length_squared(u), 14.0);
  vec3t<double> s = 2.0 * u - v / 2.0 + u * 0.5;
  EXPECT_EQ(s[0], 0.5);
}

// ---- (c) jet<interval> over boxes ----------------------------------------------------------------
TEST(Jet, IntervalJetsEncloseDerivativesOverBoxes) {
  gen g;
  long checks = 0;
  for (const auto& c : cases()) {
    double max_rel_width = 0;  // of f'' over the narrowest boxes, to report tightness
    int unbounded = 0;         // boxes where f'' came out unbounded
    for (int n = 0; n < 1500; ++n) {
      double w = std::pow(10.0, -9.0 + 9.0 * g.uniform()) * (c.hi - c.lo) / 2;
      if (n % 100 == 0) w = 0;  // degenerate boxes: a point evaluated with outward rounding
      double x0 = c.lo + (c.hi - c.lo - w) * g.uniform(), x1 = std::min(x0 + w, c.hi);
      jet<interval> j = c.fi(jet_variable(interval(x0, x1)));
      ASSERT_TRUE(sane(j)) << c.name;
      auto pts = g.points(interval(x0, x1));
      for (int i = 0; i <= 16; ++i) pts.push_back(std::clamp(x0 + (x1 - x0) * i / 16.0, x0, x1));
      for (double x : pts) {
        ref3 r = c.ref(x);
        ASSERT_TRUE(encloses(j.v, r.v) && encloses(j.d, r.d) && encloses(j.dd, r.dd))
            << c.name << " over [" << x0 << ", " << x1 << "] at " << x << ": v " << (double)r.v
            << " in " << ::testing::PrintToString(j.v) << ", d " << (double)r.d << " in "
            << ::testing::PrintToString(j.d) << ", dd " << (double)r.dd << " in "
            << ::testing::PrintToString(j.dd);
        checks += 3;
      }
      if (!is_finite(j.dd)) ++unbounded;
      if (w > 0 && w < 1e-7 * (c.hi - c.lo) && is_finite(j.dd)) {
        ref3 r = c.ref(x0);
        max_rel_width = std::max(max_rel_width, width(j.dd) / std::max(1.0, (double)std::fabs(r.dd)));
      }
    }
    std::printf("[          ] %-6s widest finite f'' enclosure over boxes narrower than 1e-7 of the range: "
                "%.2e (relative); f'' unbounded on %d of 1500 boxes\n",
                c.name, max_rel_width, unbounded);
    // Narrow boxes must give tight bounds, not just entire().
    EXPECT_LT(max_rel_width, 1e-3) << c.name;
  }
  std::printf("[          ] %ld enclosure checks\n", checks);
}

// The use case: the ray-sphere distance over boxes that shrink around a point converges to the
// point's second derivative, and a box straddling a tangency (discriminant reaching 0) is unbounded.
TEST(Jet, RaySphereBoundsShrinkWithTheBox) {
  const double xc = 0.3;
  ref3 r = ray_t_ref(xc);
  double prev = inf;
  for (double h : {0.2, 0.05, 0.01, 1e-3, 1e-4, 1e-6}) {
    jet<interval> j = ray_t(jet_variable(interval(xc - h, xc + h)));
    ASSERT_TRUE(encloses(j.dd, r.dd));
    EXPECT_LT(width(j.dd), prev);
    prev = width(j.dd);
  }
  EXPECT_LT(prev, 1e-4);
  // The line family is tangent near x = 0.79; a box across it has an unbounded t''.
  jet<interval> j = ray_t(jet_variable(interval(0.6, 1.0)));
  EXPECT_TRUE(sane(j));
  EXPECT_TRUE(is_entire(j.dd));
}

// pow's clamped form keeps f'' finite across the edge of a highlight lobe; max0 gives up there.
TEST(Jet, HighlightLobeEdge) {
  jet<interval> via_max0 = f5(jet_variable(interval(0.9, 1.1)));
  jet<interval> clamped = f6(jet_variable(interval(0.9, 1.1)));
  EXPECT_TRUE(is_entire(via_max0.dd));
  EXPECT_TRUE(is_finite(clamped.dd));
  EXPECT_TRUE(contains(clamped.dd, 0.0));
}

}  // namespace
}  // namespace epsray
