// Statistics of the mismatch diagnosis against closed-form values and constructed data.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tread_wear/diagnosis/statistics.h"

using namespace tread_wear::diagnosis;

TEST(DiagnosisStatistics, RanksAverageTies) {
  const std::vector<double> r = averageRanks({10.0, 20.0, 20.0, 5.0});
  EXPECT_DOUBLE_EQ(r[0], 2.0);
  EXPECT_DOUBLE_EQ(r[1], 3.5);
  EXPECT_DOUBLE_EQ(r[2], 3.5);
  EXPECT_DOUBLE_EQ(r[3], 1.0);
}

TEST(DiagnosisStatistics, SpearmanOfMonotoneMapIsOne) {
  std::vector<double> x, y;
  for (int i = 0; i < 12; ++i) {
    x.push_back(i);
    y.push_back(std::exp(0.3 * i));  // monotone, far from linear: Spearman 1, Pearson < 1
  }
  EXPECT_DOUBLE_EQ(spearman(x, y), 1.0);
  EXPECT_LT(pearson(x, y), 0.95);
  EXPECT_DOUBLE_EQ(olsSlope(x, std::vector<double>{0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22}), 2.0);
}

TEST(DiagnosisStatistics, TrendTestFindsATrend) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> x, trend;
  for (int i = 0; i < 30; ++i) {
    x.push_back(i);
    trend.push_back(0.2 * i + n(rng));
  }
  const TrendTest t = trendTest(x, trend, 999, 1);
  // A correlation near 0.9 with 30 points: no permutation reaches it, so p is the smallest reachable 1/1000.
  EXPECT_DOUBLE_EQ(t.p_value, 1.0 / 1000.0);
  EXPECT_NEAR(t.effect, t.slope * 29.0, 1e-12);
  EXPECT_THROW(trendTest({1, 2}, {1, 2}, 99, 1), std::invalid_argument);
}

TEST(DiagnosisStatistics, TrendTestHasItsNominalSizeUnderTheNull) {
  // Independent noise: a valid test rejects at alpha = 0.05 in 5% of the draws. 400 draws: expected 20
  // rejections, binomial sd 4.4; the window is +-3 sd.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> x(30), y(30);
  for (int i = 0; i < 30; ++i) x[i] = i;
  int rejections = 0;
  for (int draw = 0; draw < 400; ++draw) {
    for (double& v : y) v = n(rng);
    if (trendTest(x, y, 199, 100 + draw).p_value <= 0.05) ++rejections;
  }
  EXPECT_GE(rejections, 7);
  EXPECT_LE(rejections, 33);
}

TEST(DiagnosisStatistics, GroupTestEffectSize) {
  // Two groups, means 0 and 1, no spread inside: all variance is between groups.
  const std::vector<int> labels = {0, 0, 0, 0, 1, 1, 1, 1};
  const std::vector<double> y = {0, 0, 0, 0, 1, 1, 1, 1};
  const GroupTest g = groupTest(labels, y, 999, 2);
  EXPECT_DOUBLE_EQ(g.eta_squared, 1.0);
  EXPECT_DOUBLE_EQ(g.max_difference, 1.0);
  // Exactly 2 of the C(8,4) = 70 labellings reach the observed split: p ~ 2/70 (permutation estimate).
  EXPECT_NEAR(g.p_value, 2.0 / 70.0, 0.015);
}

TEST(DiagnosisStatistics, HolmAdjustment) {
  // Textbook example: p = (0.01, 0.04, 0.03, 0.005) -> sorted 0.005*4, 0.01*3, 0.03*2, 0.04*1 with monotonicity.
  const std::vector<double> adj = holmAdjust({0.01, 0.04, 0.03, 0.005});
  EXPECT_DOUBLE_EQ(adj[3], 0.02);
  EXPECT_DOUBLE_EQ(adj[0], 0.03);
  EXPECT_DOUBLE_EQ(adj[2], 0.06);
  EXPECT_DOUBLE_EQ(adj[1], 0.06);
}

TEST(DiagnosisStatistics, IncompleteBetaAndFTail) {
  EXPECT_NEAR(regularizedIncompleteBeta(1.0, 1.0, 0.3), 0.3, 1e-12);         // uniform CDF
  EXPECT_NEAR(regularizedIncompleteBeta(2.5, 2.5, 0.5), 0.5, 1e-12);         // symmetry
  EXPECT_NEAR(regularizedIncompleteBeta(2.0, 1.0, 0.6), 0.36, 1e-12);        // I_x(2,1) = x^2
  // Tabulated critical values: F(0.95; 1, 10) = 4.9646, F(0.99; 3, 20) = 4.9382.
  EXPECT_NEAR(fDistributionUpperTail(4.9646, 1, 10), 0.05, 1e-4);
  EXPECT_NEAR(fDistributionUpperTail(4.9382, 3, 20), 0.01, 1e-4);
  EXPECT_DOUBLE_EQ(fDistributionUpperTail(0.0, 2, 5), 1.0);
  // Nested test: no improvement gives p = 1.
  EXPECT_DOUBLE_EQ(nestedFTestPValue(10.0, 10.0, 1, 20), 1.0);
  EXPECT_NEAR(nestedFTestPValue(10.0 + 4.9646, 10.0, 1, 10), 0.05, 1e-4);
}

// A one-parameter linear model y = b x + e with b >= 0, fitted to pure noise (b = 0 on the bound): the boundary
// test must reject at its nominal rate, the plain test at half of it (its conservatism on a bound).
TEST(DiagnosisStatistics, BoundaryFTestHasItsNominalSizeUnderTheNull) {
  constexpr int kRuns = 20, kReplicates = 40000;
  constexpr double kAlpha = 0.05;
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> x(kRuns);
  for (int i = 0; i < kRuns; ++i) x[i] = 0.5 + 0.1 * i;
  double xx = 0.0;
  for (double v : x) xx += v * v;
  int rejected_on_bound = 0, rejected_plain = 0;
  for (int r = 0; r < kReplicates; ++r) {
    double yy = 0.0, xy = 0.0;
    for (int i = 0; i < kRuns; ++i) {
      const double y = noise(rng);
      yy += y * y;
      xy += x[i] * y;
    }
    // Constrained least squares: b = max(0, xy / xx); the RSS drops only when b is off the bound.
    const double rss_large = xy > 0.0 ? yy - xy * xy / xx : yy;
    rejected_on_bound += nestedFTestPValueOnBound(yy, rss_large, kRuns - 1) < kAlpha;
    rejected_plain += nestedFTestPValue(yy, rss_large, 1, kRuns - 1) < kAlpha;
  }
  const double se = std::sqrt(kAlpha * (1.0 - kAlpha) / kReplicates);  // binomial, ~0.0011
  EXPECT_NEAR(static_cast<double>(rejected_on_bound) / kReplicates, kAlpha, 4.0 * se);
  EXPECT_NEAR(static_cast<double>(rejected_plain) / kReplicates, 0.5 * kAlpha, 4.0 * se);
  EXPECT_DOUBLE_EQ(nestedFTestPValueOnBound(10.0, 10.0, 20), 1.0);
  EXPECT_NEAR(nestedFTestPValueOnBound(10.0 + 4.9646, 10.0, 10), 0.025, 1e-4);  // half of F(0.95; 1, 10)
}

TEST(DiagnosisStatistics, InformationCriteria) {
  // n ln(rss/n) + 2k + 2k(k+1)/(n-k-1) with rss = n: 2k + correction.
  EXPECT_NEAR(aicc(20.0, 20, 2), 4.0 + 12.0 / 17.0, 1e-12);
  EXPECT_NEAR(bic(20.0, 20, 2), 2.0 * std::log(20.0), 1e-12);
  EXPECT_TRUE(std::isinf(aicc(1.0, 3, 2)));
}

TEST(DiagnosisStatistics, WilcoxonSignedRankMatchesTheReference) {
  // R's wilcox.test example (Hollander & Wolfe, depression scores, paired, n = 9): V = 40, exact one-sided
  // p = 0.01953 = 10/512. Here the differences are the other way round, so the test "below zero" gives the same p.
  const std::vector<double> x = {1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30};
  const std::vector<double> y = {0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29};
  std::vector<double> d;
  for (std::size_t i = 0; i < x.size(); ++i) d.push_back(y[i] - x[i]);
  EXPECT_NEAR(wilcoxonSignedRankPValue(d), 10.0 / 512.0, 1e-12);
  // All of n = 5 below zero: only the all-negative assignment is as extreme, 1/32; zeros are dropped.
  EXPECT_NEAR(wilcoxonSignedRankPValue({-1.0, -2.0, -3.0, -4.0, -5.0, 0.0}), 1.0 / 32.0, 1e-12);
  EXPECT_DOUBLE_EQ(wilcoxonSignedRankPValue({0.0, 0.0}), 1.0);
}

TEST(DiagnosisStatistics, WilcoxonSignedRankWithTiesMatchesEnumeration) {
  // Tied magnitudes (average ranks): against a brute-force enumeration of the 2^n sign assignments of the ranks.
  const std::vector<double> d = {-0.5, 0.5, -1.0, -1.0, 2.0, -3.0, -3.0, -3.0, 0.25, -4.0};
  const std::vector<double> ranks = averageRanks({0.5, 0.5, 1.0, 1.0, 2.0, 3.0, 3.0, 3.0, 0.25, 4.0});
  double observed = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (d[i] > 0.0) observed += ranks[i];
  int at_most = 0;
  const int n = static_cast<int>(d.size());
  for (int mask = 0; mask < (1 << n); ++mask) {
    double w = 0.0;
    for (int i = 0; i < n; ++i)
      if (mask >> i & 1) w += ranks[i];
    if (w <= observed + 1e-9) ++at_most;
  }
  EXPECT_NEAR(wilcoxonSignedRankPValue(d), static_cast<double>(at_most) / (1 << n), 1e-12);
}

TEST(DiagnosisStatistics, WilcoxonNormalApproximationAgreesWithTheExactTest) {
  // n = 9 example above: W+ = 5, mean 22.5, variance 9 x 10 x 19 / 24 = 71.25, z = (5 - 22.5 + 0.5) / 8.441 =
  // -2.014, Phi(-2.014) = 0.0220 (normal table).
  const std::vector<double> d9 = {-0.952, 0.147, -1.022, -0.43, -0.62, -0.59, -0.49, 0.08, -0.01};
  EXPECT_NEAR(wilcoxonSignedRankPValueNormal(d9), 0.0220, 1e-4);
  // At the switch-over size the approximation matches the exact distribution, with and without ties.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (double shift : {-0.15, -0.05, 0.0}) {
    std::vector<double> d, tied;
    for (int i = 0; i < kWilcoxonExactMaxDifferences; ++i) {
      d.push_back(noise(rng) + shift);
      tied.push_back(std::round(4.0 * d.back()) / 4.0);  // many ties, some zeros
    }
    EXPECT_NEAR(wilcoxonSignedRankPValueNormal(d), wilcoxonSignedRankPValue(d), 2e-3) << shift;
    EXPECT_NEAR(wilcoxonSignedRankPValueNormal(tied), wilcoxonSignedRankPValue(tied), 2e-3) << shift;
  }
  // Beyond it (a bag cut into thousands of segments) the test takes the approximation instead of O(n^3) work.
  std::vector<double> large;
  for (int i = 0; i < 20000; ++i) large.push_back(noise(rng) - 0.02);
  const double p = wilcoxonSignedRankPValue(large);
  EXPECT_DOUBLE_EQ(p, wilcoxonSignedRankPValueNormal(large));
  EXPECT_GT(p, 0.0);
  EXPECT_LT(p, 0.5);
}

// Newcombe (1998), Statistics in Medicine 17:857, Table I, method 3 (score interval without continuity correction).
TEST(DiagnosisStatistics, WilsonIntervalMatchesNewcombe) {
  const struct {
    int k, n;
    double lower, upper;
  } cases[] = {{81, 263, 0.2553, 0.3662}, {15, 148, 0.0624, 0.1605}, {0, 20, 0.0, 0.1611}, {1, 29, 0.0061, 0.1718}};
  for (const auto& c : cases) {
    const ProportionInterval ci = wilsonInterval(c.k, c.n);
    EXPECT_NEAR(ci.lower, c.lower, 5e-5) << c.k << "/" << c.n;
    EXPECT_NEAR(ci.upper, c.upper, 5e-5) << c.k << "/" << c.n;
  }
  const ProportionInterval all = wilsonInterval(20, 20);
  EXPECT_NEAR(all.lower, 1.0 - 0.1611, 5e-5) << "symmetric to 0/20";
  EXPECT_EQ(all.upper, 1.0);
  EXPECT_THROW(wilsonInterval(3, 2), std::invalid_argument);
  EXPECT_THROW(wilsonInterval(0, 0), std::invalid_argument);
}
