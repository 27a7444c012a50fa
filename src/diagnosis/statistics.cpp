#include "tread_wear/diagnosis/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

namespace tread_wear {
namespace diagnosis {
namespace {

void checkPaired(std::size_t nx, std::size_t ny, const char* what) {
  if (nx != ny) throw std::invalid_argument(std::string(what) + ": sizes differ");
  if (nx < 3) throw std::invalid_argument(std::string(what) + ": needs at least 3 points");
}

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }

/// ln Gamma(x) for x > 0. std::lgamma also writes the sign to the global `signgam` (POSIX: MT-unsafe), a data race
/// when diagnoses run in parallel (the harness's --jobs; found by ThreadSanitizer); lgamma_r returns it instead.
double lnGamma(double x) {
  int sign = 0;
  return ::lgamma_r(x, &sign);
}

/// Between-group sum of squares of y for labels 0..G-1.
double betweenGroupSS(const std::vector<int>& labels, const std::vector<double>& y, int groups, double grand_mean,
                      std::vector<double>* sums, std::vector<int>* counts) {
  std::fill(sums->begin(), sums->end(), 0.0);
  std::fill(counts->begin(), counts->end(), 0);
  for (std::size_t i = 0; i < y.size(); ++i) {
    (*sums)[labels[i]] += y[i];
    ++(*counts)[labels[i]];
  }
  double ss = 0.0;
  for (int g = 0; g < groups; ++g) {
    if ((*counts)[g] == 0) continue;
    const double d = (*sums)[g] / (*counts)[g] - grand_mean;
    ss += (*counts)[g] * d * d;
  }
  return ss;
}

/// The non-zero differences of a signed-rank test: |d|, their average ranks and whether d > 0.
struct SignedRanks {
  std::vector<double> magnitude, ranks;
  std::vector<bool> positive;
};
SignedRanks signedRanks(const std::vector<double>& d) {
  SignedRanks sr;
  for (double v : d)
    if (v != 0.0) {
      sr.magnitude.push_back(std::abs(v));
      sr.positive.push_back(v > 0.0);
    }
  sr.ranks = averageRanks(sr.magnitude);
  return sr;
}

/// One-sided p of the signed-rank test from the normal approximation of W+ (wilcoxonSignedRankPValueNormal).
double signedRankNormalPValue(const SignedRanks& sr) {
  if (sr.ranks.empty()) return 1.0;
  const double n = static_cast<double>(sr.ranks.size());
  double w_plus = 0.0;
  for (std::size_t i = 0; i < sr.ranks.size(); ++i)
    if (sr.positive[i]) w_plus += sr.ranks[i];
  // Tie correction: each group of t equal |d| lowers the variance by (t^3 - t) / 48.
  std::vector<double> sorted = sr.magnitude;
  std::sort(sorted.begin(), sorted.end());
  double ties = 0.0;
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i;
    while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
    const double t = static_cast<double>(j - i);
    ties += t * t * t - t;
    i = j;
  }
  const double variance = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - ties / 48.0;
  if (!(variance > 0.0)) return 1.0;
  const double z = (w_plus - n * (n + 1.0) / 4.0 + 0.5) / std::sqrt(variance);  // continuity-corrected
  return std::min(1.0, 0.5 * std::erfc(-z / std::sqrt(2.0)));
}

}  // namespace

std::vector<double> averageRanks(const std::vector<double>& x) {
  std::vector<std::size_t> idx(x.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  std::vector<double> ranks(x.size());
  std::size_t i = 0;
  while (i < idx.size()) {
    std::size_t j = i;
    while (j + 1 < idx.size() && x[idx[j + 1]] == x[idx[i]]) ++j;
    const double r = 0.5 * (static_cast<double>(i) + static_cast<double>(j)) + 1.0;
    for (std::size_t k = i; k <= j; ++k) ranks[idx[k]] = r;
    i = j + 1;
  }
  return ranks;
}

double pearson(const std::vector<double>& x, const std::vector<double>& y) {
  checkPaired(x.size(), y.size(), "pearson");
  const double mx = mean(x), my = mean(y);
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 0.0 || syy <= 0.0) return 0.0;
  return sxy / std::sqrt(sxx * syy);
}

double spearman(const std::vector<double>& x, const std::vector<double>& y) {
  return pearson(averageRanks(x), averageRanks(y));
}

double olsSlope(const std::vector<double>& x, const std::vector<double>& y) {
  checkPaired(x.size(), y.size(), "olsSlope");
  const double mx = mean(x), my = mean(y);
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxx > 0.0 ? sxy / sxx : 0.0;
}

TrendTest trendTest(const std::vector<double>& x, const std::vector<double>& y, int n_permutations,
                    std::uint64_t seed) {
  checkPaired(x.size(), y.size(), "trendTest");
  TrendTest t;
  const std::vector<double> rx = averageRanks(x);
  std::vector<double> ry = averageRanks(y);
  t.rho = pearson(rx, ry);
  t.slope = olsSlope(x, y);
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  t.effect = t.slope * (*hi - *lo);
  if (t.rho == 0.0) return t;  // constant x or y: no evidence of a trend
  std::mt19937_64 rng(seed);
  int exceed = 0;
  const double obs = std::abs(t.rho) - 1e-12;  // ties with the observed value count as exceedances
  for (int k = 0; k < n_permutations; ++k) {
    std::shuffle(ry.begin(), ry.end(), rng);
    if (std::abs(pearson(rx, ry)) >= obs) ++exceed;
  }
  t.p_value = (1.0 + exceed) / (1.0 + n_permutations);
  return t;
}

GroupTest groupTest(const std::vector<int>& labels, const std::vector<double>& y, int n_permutations,
                    std::uint64_t seed) {
  checkPaired(labels.size(), y.size(), "groupTest");
  GroupTest g;
  g.groups = labels.empty() ? 0 : *std::max_element(labels.begin(), labels.end()) + 1;
  if (*std::min_element(labels.begin(), labels.end()) < 0) throw std::invalid_argument("groupTest: negative label");
  const double m = mean(y);
  double total = 0.0;
  for (double v : y) total += (v - m) * (v - m);
  std::vector<double> sums(g.groups);
  std::vector<int> counts(g.groups);
  const double obs = betweenGroupSS(labels, y, g.groups, m, &sums, &counts);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int k = 0; k < g.groups; ++k) {
    if (counts[k] == 0) continue;
    lo = std::min(lo, sums[k] / counts[k]);
    hi = std::max(hi, sums[k] / counts[k]);
  }
  g.max_difference = hi - lo;
  if (total <= 0.0 || g.groups < 2) return g;
  g.eta_squared = obs / total;
  std::mt19937_64 rng(seed);
  std::vector<int> perm = labels;
  int exceed = 0;
  for (int k = 0; k < n_permutations; ++k) {
    std::shuffle(perm.begin(), perm.end(), rng);
    if (betweenGroupSS(perm, y, g.groups, m, &sums, &counts) >= obs * (1.0 - 1e-12)) ++exceed;
  }
  g.p_value = (1.0 + exceed) / (1.0 + n_permutations);
  return g;
}

std::vector<double> holmAdjust(const std::vector<double>& p) {
  const std::size_t m = p.size();
  std::vector<std::size_t> idx(m);
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return p[a] < p[b]; });
  std::vector<double> adj(m);
  double running = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    running = std::max(running, std::min(1.0, static_cast<double>(m - k) * p[idx[k]]));
    adj[idx[k]] = running;
  }
  return adj;
}

double regularizedIncompleteBeta(double a, double b, double x) {
  if (!(a > 0.0) || !(b > 0.0) || !(x >= 0.0) || !(x <= 1.0))
    throw std::invalid_argument("regularizedIncompleteBeta: needs a, b > 0 and 0 <= x <= 1");
  if (x == 0.0 || x == 1.0) return x;
  // Symmetry I_x(a,b) = 1 - I_{1-x}(b,a) keeps the continued fraction in its fast-converging region.
  if (x > (a + 1.0) / (a + b + 2.0)) return 1.0 - regularizedIncompleteBeta(b, a, 1.0 - x);
  const double ln_front = lnGamma(a + b) - lnGamma(a) - lnGamma(b) + a * std::log(x) +
                          b * std::log1p(-x);
  // Modified Lentz evaluation of the continued fraction (Numerical Recipes, betacf).
  const double tiny = 1e-300;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < tiny) d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 500; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a - 1.0 + m2) * (a + m2));
    d = 1.0 + aa * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + 1.0 + m2));
    d = 1.0 + aa * d;
    if (std::abs(d) < tiny) d = tiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-14) break;
  }
  return std::exp(ln_front) * h / a;
}

double fDistributionUpperTail(double f, double d1, double d2) {
  if (!(d1 > 0.0) || !(d2 > 0.0)) throw std::invalid_argument("fDistributionUpperTail: needs d1, d2 > 0");
  if (!(f > 0.0)) return 1.0;
  return regularizedIncompleteBeta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f));
}

double nestedFTestPValue(double rss_small, double rss_large, int extra_parameters, int dof_large) {
  if (extra_parameters <= 0 || dof_large <= 0 || !(rss_large > 0.0) || !(rss_small > rss_large)) return 1.0;
  const double f = ((rss_small - rss_large) / extra_parameters) / (rss_large / dof_large);
  return fDistributionUpperTail(f, extra_parameters, dof_large);
}

double nestedFTestPValueOnBound(double rss_small, double rss_large, int dof_large) {
  const double p = nestedFTestPValue(rss_small, rss_large, 1, dof_large);
  return p < 1.0 ? 0.5 * p : 1.0;
}

double wilcoxonSignedRankPValue(const std::vector<double>& d) {
  const SignedRanks sr = signedRanks(d);
  if (sr.ranks.empty()) return 1.0;
  if (static_cast<int>(sr.ranks.size()) > kWilcoxonExactMaxDifferences) return signedRankNormalPValue(sr);
  // Doubled average ranks are integers, so the null distribution of 2 W+ is a count over integer sums.
  std::vector<int> doubled(sr.ranks.size());
  int observed = 0, total = 0;
  for (std::size_t i = 0; i < sr.ranks.size(); ++i) {
    doubled[i] = static_cast<int>(std::lround(2.0 * sr.ranks[i]));
    total += doubled[i];
    if (sr.positive[i]) observed += doubled[i];
  }
  // Under H0 each rank is positive with probability 1/2 independently: distribution of the sum by convolution.
  std::vector<double> probability(total + 1, 0.0);
  probability[0] = 1.0;
  int reach = 0;
  for (int r : doubled) {
    reach += r;
    for (int s = reach; s >= 0; --s) probability[s] = 0.5 * probability[s] + (s >= r ? 0.5 * probability[s - r] : 0.0);
  }
  double p = 0.0;
  for (int s = 0; s <= observed; ++s) p += probability[s];
  return std::min(1.0, p);
}

double wilcoxonSignedRankPValueNormal(const std::vector<double>& d) { return signedRankNormalPValue(signedRanks(d)); }

ProportionInterval wilsonInterval(int successes, int trials, double z) {
  if (trials < 1 || successes < 0 || successes > trials)
    throw std::invalid_argument("wilsonInterval: need 0 <= successes <= trials and trials >= 1, got " +
                                std::to_string(successes) + " of " + std::to_string(trials));
  const double n = trials, p = successes / n, z2 = z * z;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = z * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / (1.0 + z2 / n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double aicc(double rss, int n, int k) {
  if (n - k - 1 <= 0 || !(rss > 0.0)) return std::numeric_limits<double>::infinity();
  return n * std::log(rss / n) + 2.0 * k + 2.0 * k * (k + 1.0) / (n - k - 1.0);
}

double bic(double rss, int n, int k) {
  if (n <= 0 || !(rss > 0.0)) return std::numeric_limits<double>::infinity();
  return n * std::log(rss / n) + k * std::log(static_cast<double>(n));
}

}  // namespace diagnosis
}  // namespace tread_wear
