// Metrics (Eqs 4, 5, 21, 24, ERI) against hand-computed values, and Eq 23 load binning against analytic cases.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "tread_wear/fitting/metrics.h"
#include "tread_wear/model/load_binning.h"

namespace tread_wear {
namespace {

// Hand-computed values below are exact in decimal; the only error is double rounding of a few operations.
constexpr double kRoundingTol = 1e-14;

TEST(Metrics, HandComputedValues) {
  // Eq 21: residuals 1, 0, 2 -> sqrt(5/3).
  EXPECT_NEAR(rmse({1, 2, 3}, {2, 2, 5}), std::sqrt(5.0 / 3.0), kRoundingTol);
  // Eq 24: ratios 3/2 - 1 = 0.5 and 3/4 - 1 = -0.25 -> sqrt((0.25 + 0.0625)/2).
  const std::vector<double> ratios = errorRatios({2, 4}, {3, 3});
  EXPECT_NEAR(ratios[0], 0.5, kRoundingTol);
  EXPECT_NEAR(ratios[1], -0.25, kRoundingTol);
  EXPECT_NEAR(rmser({2, 4}, {3, 3}), std::sqrt(0.15625), kRoundingTol);
  // Eq 4: residual sum 1, total sum of squares 2 -> 0.5; a perfect prediction -> 1.
  EXPECT_NEAR(rSquared({1, 2, 3}, {1, 2, 4}), 0.5, kRoundingTol);
  EXPECT_EQ(rSquared({1, 2, 3}, {1, 2, 3}), 1.0);
  // Eq 5 (population form): 0.9 and 1.1 around mean 1 -> 0.1; 4 samples 1,2,3,4: mean 2.5,
  // deviations -0.6, -0.2, 0.2, 0.6 -> sqrt(0.8/4) = sqrt(0.2).
  EXPECT_NEAR(relativeStandardDeviation({0.9, 1.1}), 0.1, kRoundingTol);
  EXPECT_NEAR(relativeStandardDeviation({1, 2, 3, 4}), std::sqrt(0.2), kRoundingTol);
  EXPECT_EQ(errorRatioIndex(0.1556, 0.0832), 0.1556 / 0.0832);
}

TEST(Metrics, PaperTable5EriIsTheRmserRatio) {
  // Table 5: ERI(Opt_T) = 0.95 with RMSER(Opt) = 8.32% (Fig. 11) and RMSER(Opt_T) = 7.92% (Fig. 12):
  // 7.92/8.32 = 0.952, printed rounded to two digits.
  EXPECT_NEAR(errorRatioIndex(0.0792, 0.0832), 0.95, 0.005);
}

TEST(Metrics, BadInput) {
  EXPECT_THROW(rmse({}, {}), std::invalid_argument);
  EXPECT_THROW(rmse({1, 2}, {1}), std::invalid_argument);
  EXPECT_THROW(rmse({1, NAN}, {1, 2}), std::invalid_argument);
  EXPECT_THROW(rmser({0, 1}, {1, 1}), std::invalid_argument);
  EXPECT_THROW(rSquared({2, 2}, {1, 3}), std::invalid_argument);
  EXPECT_THROW(relativeStandardDeviation({1, -1}), std::invalid_argument);
  EXPECT_THROW(errorRatioIndex(0.1, 0.0), std::invalid_argument);
}

double sumOfWeights(const std::vector<LoadBin>& bins) {
  double s = 0.0;
  for (const LoadBin& b : bins) s += b.weight;
  return s;
}

TEST(LoadBinning, LinearFunctionGivesTheValueAtTheMean) {
  // Symmetric bins with symmetric weights: sum beta_i (a + b x_i) = a + b mean, up to rounding.
  const auto linear = [](double load_n) { return 3e-7 + 4e-9 * load_n; };
  for (double std_n : {0.5, 3.0, 7.0, 15.0}) {  // all bins stay above 0 N (no truncation)
    const std::vector<LoadBin> bins = normalLoadBins(75.0, std_n);
    EXPECT_NEAR(sumOfWeights(bins), 1.0, kRoundingTol);
    EXPECT_NEAR(binnedAverage(bins, linear), linear(75.0), 1e-12 * linear(75.0)) << "std " << std_n;
  }
}

TEST(LoadBinning, QuadraticGainsHalfTheCurvatureTimesTheBinnedVariance) {
  // f = x^2: E f = mean^2 + var. Evaluating at bin centres of width w adds w^2/12 to the variance (Sheppard);
  // for w = sigma/4 the remaining error of that correction is of order exp(-2 pi^2 sigma^2/w^2), nil, and a
  // span of 8 sigma cuts off a tail probability of 1e-15.
  LoadBinningOptions options;
  options.bin_width_n = 2.0;
  options.span_sigmas = 8.0;
  const double mean = 75.0;
  const double sigma = 8.0;
  const double expected = mean * mean + sigma * sigma + options.bin_width_n * options.bin_width_n / 12.0;
  const double binned = binnedAverage(normalLoadBins(mean, sigma, options), [](double x) { return x * x; });
  EXPECT_NEAR(binned, expected, 1e-10 * expected);
}

TEST(LoadBinning, DefaultsAndEdgeCases) {
  // No scatter (0 or unknown): one bin at the mean.
  for (double std_n : {0.0, std::nan("")}) {
    const std::vector<LoadBin> bins = normalLoadBins(60.0, std_n);
    ASSERT_EQ(bins.size(), 1u);
    EXPECT_EQ(bins[0].centre_n, 60.0);
    EXPECT_EQ(bins[0].weight, 1.0);
  }
  // Paper's 10 N bins: std 3 N within +-4 sigma = +-12 N -> centres 65, 75, 85 (the outer bins reach 90 N).
  const std::vector<LoadBin> bins = normalLoadBins(75.0, 3.0);
  ASSERT_EQ(bins.size(), 3u);
  EXPECT_EQ(bins[0].centre_n, 65.0);
  EXPECT_EQ(bins[2].centre_n, 85.0);
  // Central bin share = P(|z| < 5/3) / P(|z| < 5) for a normal: erf(5/(3 sqrt 2)) / erf(5/sqrt 2).
  EXPECT_NEAR(bins[1].weight, std::erf(5.0 / (3.0 * std::sqrt(2.0))) / std::erf(5.0 / std::sqrt(2.0)), 1e-14);
  // Loads stay positive: bins at or below 0 N are dropped.
  for (const LoadBin& b : normalLoadBins(5.0, 10.0)) EXPECT_GT(b.centre_n, 0.0);
  EXPECT_NEAR(sumOfWeights(normalLoadBins(5.0, 10.0)), 1.0, kRoundingTol);
}

TEST(LoadBinning, RecordedSamples) {
  // 71, 74, 76, 79 in [70, 80) and 81 in [80, 90): shares 0.8 at 75 N and 0.2 at 85 N.
  const std::vector<LoadBin> bins = sampleLoadBins({71, 74, 76, 79, 81});
  ASSERT_EQ(bins.size(), 2u);
  EXPECT_EQ(bins[0].centre_n, 75.0);
  EXPECT_NEAR(bins[0].weight, 0.8, kRoundingTol);
  EXPECT_EQ(bins[1].centre_n, 85.0);
  EXPECT_NEAR(binnedAverage(bins, [](double x) { return 2.0 * x + 1.0; }), 0.8 * 151.0 + 0.2 * 171.0, 1e-12);
}

TEST(LoadBinning, BadInput) {
  EXPECT_THROW(normalLoadBins(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(normalLoadBins(75.0, -1.0), std::invalid_argument);
  EXPECT_THROW(normalLoadBins(75.0, INFINITY), std::invalid_argument);
  LoadBinningOptions bad;
  bad.bin_width_n = 0.0;
  EXPECT_THROW(normalLoadBins(75.0, 3.0, bad), std::invalid_argument);
  EXPECT_THROW(sampleLoadBins({}), std::invalid_argument);
  EXPECT_THROW(sampleLoadBins({75.0, -2.0}), std::invalid_argument);
  EXPECT_THROW(sampleLoadBins({75.0, NAN}), std::invalid_argument);
}

}  // namespace
}  // namespace tread_wear
