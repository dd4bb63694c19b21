// predicate/affine.h: every operation must ENCLOSE. A form c + sum_i x_i e_i +- r is checked
// at random points e of [-1, 1]^4 (and random noise within r): the exact result of the
// operation on the input's value there, in long double, must lie within the result form's
// radius r' of the result's own linear part at e. Also: over wide ranges the secant forms
// keep sqrt, 1/x and x^k bounded and narrow, where the tangent's remainder made directions
// normalized over a wide cell unbounded.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "predicate/affine.h"

namespace epsray {
namespace {

// A form whose range is [l, h], spread over the four coordinates with random weights.
affine form_over(double l, double h, std::mt19937& rng, double noise_share = 0.0) {
  std::uniform_real_distribution<double> u(0.05, 1.0);
  double wsum = 0, w[4];
  for (double& x : w) x = u(rng), wsum += x;
  affine a(0.5 * (l + h));
  const double half = 0.5 * (h - l);
  for (int i = 0; i < 4; ++i) a.x[i] = half * (1 - noise_share) * w[i] / wsum;
  a.r = half * noise_share;
  return a;
}

long double linear_at(const affine& a, const long double e[4]) {
  long double v = a.c;
  for (int i = 0; i < 4; ++i) v += (long double)a.x[i] * e[i];
  return v;
}

// For many points of the cell: f(a's value) lies in result's range at that point.
void expect_encloses(const affine& a, const affine& result, const std::function<long double(long double)>& f,
                     std::mt19937& rng, const char* what) {
  ASSERT_TRUE(std::isfinite(result.r)) << what << ": unbounded over [" << lo(a) << ", " << hi(a) << "]";
  std::uniform_real_distribution<double> u(-1, 1);
  for (int s = 0; s < 400; ++s) {
    long double e[4];
    for (long double& x : e) x = s < 16 ? ((s >> (&x - e)) & 1 ? 1 : -1) : u(rng);  // corners first
    const long double v = linear_at(a, e) + (long double)a.r * (s % 3 == 0 ? 1 : (s % 3 == 1 ? -1 : u(rng)));
    const long double want = f(v);
    const long double got = linear_at(result, e);
    ASSERT_LE(std::fabs(want - got), (long double)result.r)
        << what << " at x = " << (double)v << " over [" << lo(a) << ", " << hi(a) << "]: exact " << (double)want
        << ", form " << (double)got << " +- " << result.r;
  }
}

TEST(Affine, SqrtRecipAndPowEncloseOverNarrowAndWideRanges) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> mag(-3, 3), ratio(0.001, 4.5);
  for (int rep = 0; rep < 300; ++rep) {
    const double l = std::pow(10.0, mag(rng)), h = l * std::pow(10.0, ratio(rng));
    const double noise = rep % 4 == 0 ? 0.1 : 0.0;
    affine a = form_over(l, h, rng, noise);
    expect_encloses(a, sqrt(a), [](long double x) { return std::sqrt(x); }, rng, "sqrt");
    expect_encloses(a, recip(a), [](long double x) { return 1 / x; }, rng, "1/x");
    affine neg = -a;
    expect_encloses(neg, recip(neg), [](long double x) { return 1 / x; }, rng, "1/x of a negative range");
    for (double k : {0.5, 2.0, 3.0827, 40.0, 400.0}) {
      if (k * std::log10(h) > 250) continue;  // x^k overflows: unbounded is the right answer
      expect_encloses(a, pow(a, k), [k](long double x) { return std::pow(x, (long double)k); }, rng, "x^k");
    }
  }
}

TEST(Affine, WideRangesStayBoundedAndNarrow) {
  // sqrt over [0.2, 16]: the true range is 3.55 wide. The tangent at the midpoint carries a
  // remainder of max|phi''| w^2 / 8 = 75 there; the secant form stays within 3.
  std::mt19937 rng(5);
  affine a = form_over(0.2, 16, rng);
  affine s = sqrt(a);
  EXPECT_LT(s.radius(), 3.0);
  EXPECT_GT(lo(s), 0.0);
  EXPECT_LT(hi(s), 5.0);  // sqrt(16) = 4, plus the secant gap (0.71)
  // 1/x over [0.46, 3.98] (a direction's length over a wide cell): finite and narrower than
  // the tangent's remainder alone (2 / 0.46^3 * 3.52^2 / 8 = 31.8).
  affine b = form_over(0.46, 3.98, rng);
  affine r = recip(b);
  EXPECT_TRUE(std::isfinite(r.radius()));
  EXPECT_LT(r.radius(), 2.0);
  // x^40 over [0.5, 0.9]: x^40 stays within [0, 0.0148] and the form too.
  affine c = form_over(0.5, 0.9, rng);
  affine p = pow(c, 40.0);
  EXPECT_LT(hi(p), 0.03);
  EXPECT_GT(lo(p), -0.03);
}

TEST(Affine, RangeFormHoldsItsEnds) {
  affine a = affine_range(0.25, 7.5);
  EXPECT_LE(lo(a), 0.25);
  EXPECT_GE(hi(a), 7.5);
  EXPECT_LT(a.radius(), 3.7);
  for (double x : a.x) EXPECT_EQ(x, 0.0);
  // A range with an infinite end is unbounded, not NaN.
  affine u = affine_range(1.0, INFINITY);
  EXPECT_FALSE(std::isfinite(u.r));
}

TEST(Affine, SecantNeverNaNAtDegenerateRanges) {
  // A point range (w = 0) and a range touching 0 must not produce NaN forms.
  affine p(2.0);
  affine s = sqrt(p), r = recip(p), k = pow(p, 3.5);
  EXPECT_NEAR(s.c, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.c, 0.5, 1e-12);
  EXPECT_NEAR(k.c, std::pow(2.0, 3.5), 1e-9);
  for (const affine& f : {s, r, k}) EXPECT_FALSE(std::isnan(f.r));
  std::mt19937 rng(9);
  affine z = form_over(0.0, 1.0, rng);
  EXPECT_FALSE(std::isfinite(sqrt(z).r));
  EXPECT_FALSE(std::isfinite(recip(z).r));
}

}  // namespace
}  // namespace epsray
