#pragma once
/// @file statistics.h
/// Small, dependency-free statistics for the mismatch diagnosis: rank correlation and regression slope with
/// permutation p-values, between-group effect size (eta squared) with a permutation p-value, Holm's step-down
/// adjustment for many tests, the F distribution's tail (nested model comparison), the Wilcoxon signed-rank test
/// of paired differences (held-out errors of two models) and the information criteria AICc and BIC of a Gaussian
/// least-squares fit.
///
/// Permutation p-values are (1 + #{|stat_perm| >= |stat_obs|}) / (1 + n_permutations) (Phipson & Smyth, 2010):
/// exact-size tests that never return 0, so the smallest reachable p is 1 / (1 + n_permutations).
/// Ties in ranks get the average rank. Everything is deterministic for a given seed.

#include <cstdint>
#include <string>
#include <vector>

namespace tread_wear {
namespace diagnosis {

/// Average ranks (1-based) with ties sharing the mean rank.
std::vector<double> averageRanks(const std::vector<double>& x);
/// Pearson correlation; 0 when either variable is constant.
double pearson(const std::vector<double>& x, const std::vector<double>& y);
/// Spearman's rank correlation (Pearson on average ranks).
double spearman(const std::vector<double>& x, const std::vector<double>& y);
/// Ordinary least-squares slope of y on x; 0 when x is constant.
double olsSlope(const std::vector<double>& x, const std::vector<double>& y);

struct TrendTest {
  double rho = 0.0;          ///< Spearman rank correlation [-]
  double slope = 0.0;        ///< OLS slope of y on x [unit of y per unit of x]
  double effect = 0.0;       ///< slope times the observed range of x [unit of y]
  double p_value = 1.0;      ///< two-sided permutation p-value of |rho|
};
/// Trend of y over x with a permutation test on |rho|. @throw std::invalid_argument for sizes < 3 or mismatched.
TrendTest trendTest(const std::vector<double>& x, const std::vector<double>& y, int n_permutations,
                    std::uint64_t seed);

struct GroupTest {
  double eta_squared = 0.0;  ///< between-group share of the variance of y [-]
  double max_difference = 0.0;  ///< largest minus smallest group mean [unit of y]
  int groups = 0;
  double p_value = 1.0;      ///< permutation p-value of the between-group sum of squares
};
/// Differences between groups (labels 0..G-1). @throw std::invalid_argument for sizes < 3 or mismatched.
GroupTest groupTest(const std::vector<int>& labels, const std::vector<double>& y, int n_permutations,
                    std::uint64_t seed);

/// Holm's step-down adjusted p-values (family-wise error control), aligned with the input.
std::vector<double> holmAdjust(const std::vector<double>& p_values);

/// Regularised incomplete beta function I_x(a, b), a, b > 0, 0 <= x <= 1 (continued fraction).
double regularizedIncompleteBeta(double a, double b, double x);
/// Upper tail P(F > f) of the F distribution with (d1, d2) degrees of freedom; 1 for f <= 0.
double fDistributionUpperTail(double f, double d1, double d2);
/// p-value of the partial F test of a larger nested model: RSS drops from rss_small to rss_large with
/// extra_parameters more, residual degrees of freedom dof_large = n - k_large. 1 when nothing improved.
double nestedFTestPValue(double rss_small, double rss_large, int extra_parameters, int dof_large);
/// The same test for one extra parameter whose no-effect value lies on a bound of its admissible range (a rate, a
/// compliance or a scale that cannot be negative). Under the null the constrained estimate sits on the bound half
/// the time, leaving the RSS unchanged, and the statistic follows F(1, dof) otherwise: the null distribution is the
/// mixture 0.5 delta_0 + 0.5 F(1, dof) (chi-bar-squared; Self and Liang 1987, case 5; Chernoff 1954), so the
/// p-value is half the plain one. The plain test is conservative there by a factor of 2. 1 when nothing improved.
double nestedFTestPValueOnBound(double rss_small, double rss_large, int dof_large);

/// One-sided Wilcoxon signed-rank test that paired differences d_i are centred below zero: the exact null
/// distribution of the positive-rank sum W+ (each rank positive with probability 1/2; average ranks for ties in
/// |d|, zero differences dropped), p = P(W+ <= observed). 1 when every difference is zero. Exact also with ties
/// (doubled average ranks are integers); time O(n^3), fine for the few hundred runs of a rig program. Above
/// kWilcoxonExactMaxDifferences non-zero differences (a bag cut into thousands of segments) it returns the normal
/// approximation below instead, whose error there is far below any significance level (and which does not
/// underflow in the far tail as the exact sum does).
double wilcoxonSignedRankPValue(const std::vector<double>& differences);
constexpr int kWilcoxonExactMaxDifferences = 400;
/// The same one-sided p from the normal approximation of W+ (mean n(n+1)/4, variance n(n+1)(2n+1)/24 less
/// sum(t^3 - t)/48 over groups of t tied |d|, continuity correction 1/2); O(n log n).
double wilcoxonSignedRankPValueNormal(const std::vector<double>& differences);

/// Wilson score interval of a binomial proportion (no continuity correction; Newcombe 1998, method 3): the
/// uncertainty of a success rate measured on `trials` cases. z = 1.96 gives the 95% interval.
/// @throw std::invalid_argument unless 0 <= successes <= trials and trials >= 1.
struct ProportionInterval {
  double lower = 0.0, upper = 1.0;
};
ProportionInterval wilsonInterval(int successes, int trials, double z = 1.959963984540054);

/// Corrected Akaike criterion of a Gaussian least-squares fit: n ln(rss/n) + 2k + 2k(k+1)/(n-k-1).
/// +inf when n - k - 1 <= 0.
double aicc(double rss, int n, int k);
/// Bayesian (Schwarz) criterion: n ln(rss/n) + k ln(n).
double bic(double rss, int n, int k);

}  // namespace diagnosis
}  // namespace tread_wear
