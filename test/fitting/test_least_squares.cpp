// Bounded least squares (least_squares.h) on manufactured problems with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "tread_wear/fitting/least_squares.h"

namespace tread_wear {
namespace {

// Exponential decay y = A exp(-k t) sampled at 12 points.
struct DecayData {
  std::vector<double> t, y;
};

DecayData makeDecay(double a, double k, double noise_sigma, unsigned seed) {
  DecayData d;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sigma);
  for (int i = 0; i < 12; ++i) {
    const double t = 0.25 * i;
    d.t.push_back(t);
    d.y.push_back(a * std::exp(-k * t) + (noise_sigma > 0.0 ? noise(rng) : 0.0));
  }
  return d;
}

LeastSquaresProblem decayProblem(const DecayData& d) {
  LeastSquaresProblem p;
  p.parameters = {{"A", 1.0, 0.01, 100.0, true}, {"k", 0.5, 0.0, 10.0, false}};
  p.num_records = static_cast<int>(d.t.size());
  p.residuals = [d](const std::vector<double>& v, const std::vector<int>& recs, double* r) {
    for (size_t i = 0; i < recs.size(); ++i) r[i] = v[0] * std::exp(-v[1] * d.t[recs[i]]) - d.y[recs[i]];
    return true;
  };
  return p;
}

TEST(LeastSquares, RecoversKnownParametersFromNoiseFreeData) {
  const LeastSquaresSummary s = solveLeastSquares(decayProblem(makeDecay(3.0, 1.3, 0.0, 1)), {});
  ASSERT_TRUE(s.usable) << s.message;
  EXPECT_EQ(s.termination, TerminationType::kConvergence);
  // Exact data: only the solver tolerances limit the answer (function tolerance 1e-10 on a cost ~1e-20).
  constexpr double kTol = 1e-7;
  EXPECT_NEAR(s.parameters[0].value, 3.0, kTol);
  EXPECT_NEAR(s.parameters[1].value, 1.3, kTol);
  EXPECT_LT(s.final_cost, 1e-14);
  EXPECT_GT(s.initial_cost, s.final_cost);
  EXPECT_FALSE(s.parameters[0].atBound());
}

TEST(LeastSquares, NoisyDataWithinReportedStandardErrors) {
  // 20 independent noise realisations: the truth should lie within 3 reported standard errors of
  // every estimate (a 3-sigma miss has probability 0.3% per parameter for a near-linear problem).
  int within = 0, total = 0;
  double mean_se_ratio = 0.0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const double sigma = 0.05;
    const LeastSquaresSummary s = solveLeastSquares(decayProblem(makeDecay(3.0, 1.3, sigma, seed)), {});
    ASSERT_TRUE(s.usable);
    for (int j = 0; j < 2; ++j) {
      const double truth = j == 0 ? 3.0 : 1.3;
      ASSERT_TRUE(std::isfinite(s.parameters[j].std_error));
      within += std::abs(s.parameters[j].value - truth) <= 3.0 * s.parameters[j].std_error;
      ++total;
    }
    mean_se_ratio += std::sqrt(s.residual_variance) / sigma / 20.0;
    EXPECT_EQ(s.degrees_of_freedom, 10);
  }
  EXPECT_GE(within, total - 1);
  // The residual standard deviation estimates the noise level (10 dof: ~22% scatter per run, averaged).
  EXPECT_NEAR(mean_se_ratio, 1.0, 0.15);
}

TEST(LeastSquares, LinearProblemStandardErrorsCorrelationAndConditionNumber) {
  // y = b0 x0 + b1 x1 with columns x0 = (1,1,1,1), x1 = (1,1,1,-1) + noise pattern e orthogonal to both.
  // Analytic: J^T J = [[4, 2], [2, 4]]; cosine between columns c = 0.5, so the correlation of the
  // estimates is -0.5 and cond(column-scaled J) = sqrt((1 + c)/(1 - c)) = sqrt(3).
  // Residual e = (1,-1,0,0) * 0.1: s^2 = |e|^2/(4-2) = 0.01; Cov = s^2 inv(J^T J) = 0.01/12 [[4,-2],[-2,4]].
  const double x0[4] = {1, 1, 1, 1}, x1[4] = {1, 1, 1, -1}, e[4] = {0.1, -0.1, 0.0, 0.0};
  LeastSquaresProblem p;
  p.parameters = {{"b0", 0.0}, {"b1", 0.0}};
  p.num_records = 4;
  p.residuals = [&](const std::vector<double>& v, const std::vector<int>& recs, double* r) {
    for (size_t i = 0; i < recs.size(); ++i) {
      const int k = recs[i];
      r[i] = v[0] * x0[k] + v[1] * x1[k] - (2.0 * x0[k] - 1.0 * x1[k] + e[k]);
    }
    return true;
  };
  const LeastSquaresSummary s = solveLeastSquares(p, {});
  ASSERT_TRUE(s.usable);
  constexpr double kTol = 1e-6;  // linear problem, finite differences exact up to rounding
  EXPECT_NEAR(s.parameters[0].value, 2.0, kTol);
  EXPECT_NEAR(s.parameters[1].value, -1.0, kTol);
  EXPECT_NEAR(s.residual_variance, 0.01, kTol);
  EXPECT_NEAR(s.parameters[0].std_error, std::sqrt(0.01 * 4.0 / 12.0), kTol);
  EXPECT_NEAR(s.parameters[1].std_error, std::sqrt(0.01 * 4.0 / 12.0), kTol);
  EXPECT_NEAR(s.correlation(0, 1), -0.5, kTol);
  EXPECT_NEAR(s.condition_number, std::sqrt(3.0), kTol);
}

// Straight line y = 1 + 2 x on x in [0, 1] with noise whose standard deviation grows 26-fold towards the ends
// (where the slope is decided): over many noise draws, the truth must lie within the t-quantile of the reported
// standard error at the nominal 95% with the sandwich (HC3), while the classic s^2 (J^T J)^-1 understates it.
TEST(LeastSquares, RobustStandardErrorsCoverUnderHeteroscedasticNoise) {
  constexpr int kPoints = 30, kDraws = 1500;
  constexpr double kT975 = 2.048;  // t distribution, 28 degrees of freedom
  std::vector<double> x(kPoints), sd(kPoints), y(kPoints);
  for (int i = 0; i < kPoints; ++i) {
    x[i] = static_cast<double>(i) / (kPoints - 1);
    sd[i] = 0.1 + 10.0 * (x[i] - 0.5) * (x[i] - 0.5);  // 0.1 in the middle, 2.6 at the ends
  }
  LeastSquaresProblem p;
  p.parameters = {{"intercept", 0.0}, {"slope", 0.0}};
  p.num_records = kPoints;
  p.residuals = [&](const std::vector<double>& v, const std::vector<int>& recs, double* r) {
    for (size_t i = 0; i < recs.size(); ++i) r[i] = v[0] + v[1] * x[recs[i]] - y[recs[i]];
    return true;
  };
  LeastSquaresOptions classic, robust;
  robust.robust_covariance = true;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  int covered_classic = 0, covered_robust = 0;
  for (int d = 0; d < kDraws; ++d) {
    for (int i = 0; i < kPoints; ++i) y[i] = 1.0 + 2.0 * x[i] + sd[i] * noise(rng);
    const LeastSquaresSummary a = solveLeastSquares(p, classic), b = solveLeastSquares(p, robust);
    ASSERT_TRUE(a.usable && b.usable);
    EXPECT_DOUBLE_EQ(a.parameters[1].value, b.parameters[1].value) << "the estimate does not depend on the covariance";
    covered_classic += std::abs(a.parameters[1].value - 2.0) <= kT975 * a.parameters[1].std_error;
    covered_robust += std::abs(b.parameters[1].value - 2.0) <= kT975 * b.parameters[1].std_error;
  }
  const double se = std::sqrt(0.95 * 0.05 / kDraws);  // binomial, ~0.0056
  EXPECT_NEAR(static_cast<double>(covered_robust) / kDraws, 0.95, 3.0 * se) << covered_classic;
  EXPECT_LT(static_cast<double>(covered_classic) / kDraws, 0.95 - 3.0 * se) << covered_robust;
}

TEST(LeastSquares, BoundsAreRespectedAndReported) {
  // Unconstrained optimum A = 3; the upper bound 2 must hold and be flagged.
  LeastSquaresProblem p = decayProblem(makeDecay(3.0, 1.3, 0.0, 1));
  p.parameters[0].upper = 2.0;
  const LeastSquaresSummary s = solveLeastSquares(p, {});
  ASSERT_TRUE(s.usable);
  EXPECT_LE(s.parameters[0].value, 2.0);
  EXPECT_TRUE(s.parameters[0].at_upper);
  EXPECT_TRUE(std::isnan(s.parameters[0].std_error));
  EXPECT_FALSE(s.parameters[1].atBound());
  EXPECT_TRUE(std::isfinite(s.parameters[1].std_error));
}

TEST(LeastSquares, WithoutTheBoundedLineSearchTheConstrainedOptimumIsReachedWithFewerEvaluations) {
  // y = a + b t with a held below its unconstrained value by the bound a <= 1: the constrained optimum is a = 1 and
  // b = sum t (y - 1) / sum t^2 (the normal equation of b alone). Ceres's projected steps alone crawl along the
  // bound and stop short of it on the parameter tolerance (b 0.977 for 1.017 after 61 iterations); holding the
  // parameter that settles on its bound (hold_bound_parameters) reaches it, with either line-search setting, and
  // without the line search (whose cubic interpolation takes a Jacobian at every trial step) with fewer residual
  // evaluations.
  std::vector<double> t, y;
  for (int i = 0; i < 10; ++i) {
    t.push_back(0.5 * i);
    y.push_back(2.0 + 0.7 * t.back() + 0.05 * std::sin(3.0 * i));
  }
  double st2 = 0.0, sty = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    st2 += t[i] * t[i];
    sty += t[i] * (y[i] - 1.0);
  }
  const double b_expected = sty / st2;
  int evaluations = 0;
  LeastSquaresProblem p;
  p.parameters = {{"a", 0.5, -5.0, 1.0, false}, {"b", 0.1, -5.0, 5.0, false}};
  p.num_records = static_cast<int>(t.size());
  p.residuals = [&](const std::vector<double>& v, const std::vector<int>& recs, double* r) {
    ++evaluations;
    for (std::size_t i = 0; i < recs.size(); ++i) r[i] = v[0] + v[1] * t[recs[i]] - y[recs[i]];
    return true;
  };
  int used[2] = {0, 0};
  for (const bool line_search : {true, false}) {
    LeastSquaresOptions options;
    options.bounded_line_search = line_search;
    options.hold_bound_parameters = true;
    evaluations = 0;
    const LeastSquaresSummary s = solveLeastSquares(p, options);
    ASSERT_TRUE(s.usable) << s.message;
    EXPECT_NEAR(s.parameters[0].value, 1.0, 1e-9);
    EXPECT_TRUE(s.parameters[0].at_upper);
    EXPECT_NEAR(s.parameters[1].value, b_expected, 1e-7 * std::abs(b_expected));
    used[line_search ? 0 : 1] = evaluations;
  }
  EXPECT_LT(used[1], used[0]);
  std::printf("residual evaluations: %d with the line search, %d without\n", used[0], used[1]);
}

TEST(LeastSquares, PriorPullsTowardItsCentre) {
  // One datum y = 5 for a parameter with a prior centred at 1: the estimate is the precision-weighted
  // mean. Data residual (b - 5)/1, prior residual (b - 1)/sigma with b linear (scale = |initial| = 1):
  // b = (5 + 1/sigma^2) / (1 + 1/sigma^2). For sigma = 0.5: (5 + 4)/5 = 1.8.
  LeastSquaresProblem p;
  p.parameters = {{"b", 1.0}};
  p.parameters[0].prior_value = 1.0;
  p.parameters[0].prior_sigma = 0.5;
  p.num_records = 1;
  p.residuals = [](const std::vector<double>& v, const std::vector<int>&, double* r) {
    r[0] = v[0] - 5.0;
    return true;
  };
  const LeastSquaresSummary s = solveLeastSquares(p, {});
  ASSERT_TRUE(s.usable);
  EXPECT_NEAR(s.parameters[0].value, 1.8, 1e-7);
  p.parameters[0].prior_value = std::numeric_limits<double>::quiet_NaN();
  p.parameters[0].prior_sigma = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NEAR(solveLeastSquares(p, {}).parameters[0].value, 5.0, 1e-7);
}

TEST(LeastSquares, InvalidProblemsAreRejectedWithNamedField) {
  LeastSquaresProblem p = decayProblem(makeDecay(3.0, 1.3, 0.0, 1));
  std::string err;
  p.parameters[0].initial = 200.0;
  EXPECT_FALSE(p.validate(&err));
  EXPECT_NE(err.find("'A'"), std::string::npos) << err;
  p.parameters[0].initial = 1.0;
  p.parameters[0].lower = -1.0;
  EXPECT_FALSE(p.validate(&err));
  EXPECT_NE(err.find("log scale"), std::string::npos) << err;
  p.parameters[0].lower = 0.01;
  p.groups = {"a"};
  EXPECT_FALSE(p.validate(&err));
  EXPECT_NE(err.find("groups"), std::string::npos) << err;
  const LeastSquaresSummary s = solveLeastSquares(p, {});
  EXPECT_EQ(s.termination, TerminationType::kFailure);
  EXPECT_FALSE(s.usable);
  LeastSquaresOptions o;
  o.jacobian_step = 0.0;
  EXPECT_FALSE(o.validate(&err));
  EXPECT_NE(err.find("jacobian_step"), std::string::npos);
}

TEST(LeastSquares, FailingResidualFunctionIsReported) {
  LeastSquaresProblem p = decayProblem(makeDecay(3.0, 1.3, 0.0, 1));
  p.residuals = [](const std::vector<double>&, const std::vector<int>&, double*) { return false; };
  const LeastSquaresSummary s = solveLeastSquares(p, {});
  EXPECT_FALSE(s.usable);
  EXPECT_EQ(s.termination, TerminationType::kFailure);
}

TEST(CrossValidation, FoldsGroupRecordsAndHoldThemOutTogether) {
  LeastSquaresProblem p;
  p.parameters = {{"mean", 0.0}};
  p.num_records = 5;
  p.groups = {"a", "b", "a", "c", "b"};
  const double y[5] = {1.0, 2.0, 3.0, 4.0, 6.0};
  p.residuals = [&](const std::vector<double>& v, const std::vector<int>& recs, double* r) {
    for (size_t i = 0; i < recs.size(); ++i) r[i] = v[0] - y[recs[i]];
    return true;
  };
  const auto folds = crossValidationFolds(p);
  ASSERT_EQ(folds.size(), 3u);
  EXPECT_EQ(folds[0].first, "a");
  EXPECT_EQ(folds[0].second, (std::vector<int>{0, 2}));
  EXPECT_EQ(folds[1].second, (std::vector<int>{1, 4}));
  EXPECT_EQ(folds[2].second, (std::vector<int>{3}));

  // Fitting a mean: the fold without "a" fits mean(2, 4, 6) = 4, so the held-out residuals of records
  // 0 and 2 are 4 - 1 = 3 and 4 - 3 = 1; without "b": mean(1, 3, 4) = 8/3; without "c": mean(1,2,3,6) = 3.
  const CrossValidationResult cv = crossValidate(p, {});
  ASSERT_EQ(cv.held_out_residuals.size(), 5u);
  constexpr double kTol = 1e-7;
  EXPECT_NEAR(cv.held_out_residuals[0], 3.0, kTol);
  EXPECT_NEAR(cv.held_out_residuals[2], 1.0, kTol);
  EXPECT_NEAR(cv.held_out_residuals[1], 8.0 / 3.0 - 2.0, kTol);
  EXPECT_NEAR(cv.held_out_residuals[4], 8.0 / 3.0 - 6.0, kTol);
  EXPECT_NEAR(cv.held_out_residuals[3], 3.0 - 4.0, kTol);
  EXPECT_NEAR(cv.folds[2].values[0], 3.0, kTol);

  // No groups: leave-one-record-out.
  p.groups.clear();
  EXPECT_EQ(crossValidationFolds(p).size(), 5u);
}

}  // namespace
}  // namespace tread_wear
