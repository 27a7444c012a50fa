#include "tread_wear/diagnosis/numerics_check.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>

namespace tread_wear {
namespace diagnosis {
namespace {

/// Forward-difference step of the Jacobian, as a fraction of a parameter's scale (|value|, or its bound range when
/// the value is 0): large against the fixed grid's round-off, small against the model's curvature.
constexpr double kJacobianStep = 0.01;
/// Monte Carlo draws of the quantile q (file comment of numerics_check.h): its relative error at the 95% quantile
/// is about 2%, small against the factor 4 between two sample sizes.
constexpr int kQuantileDraws = 4000;
/// Share of the inclusion probabilities drawn uniformly over the cells (the rest in proportion to a cell's
/// contribution to the weighted predictions).
constexpr double kUniformShare = 0.1;
/// Growth of the sample when its interval straddles the limit.
constexpr double kSampleGrowth = 4.0;

/// The measured values (run, output) that the check weighs, and their noise sigma.
struct Rows {
  std::vector<std::pair<int, int>> index;
  std::map<std::pair<int, int>, int> row_of;
  std::vector<double> sigma;
};

Rows measuredRows(const DiagnosisData& data, const NoiseModel noise[kNumOutputs]) {
  Rows rows;
  for (std::size_t i = 0; i < data.runs.size(); ++i)
    for (int o = 0; o < kNumOutputs; ++o)
      if (std::isfinite(data.runs[i].measured[o])) {
        rows.row_of[{static_cast<int>(i), o}] = static_cast<int>(rows.index.size());
        rows.index.emplace_back(static_cast<int>(i), o);
        rows.sigma.push_back(noise[o].sigma(data.runs[i].measured[o]));
      }
  return rows;
}

/// The weighted Jacobian of the preset's predictions in the fitted parameters (forward differences).
Eigen::MatrixXd weightedJacobian(const ExtendedModel& model, const std::vector<double>& values, const Prediction& at,
                                 const Rows& rows, const std::string& label) {
  const std::vector<FitParameter> params = model.parameters();
  const int m = static_cast<int>(rows.index.size());
  Eigen::MatrixXd wj(m, static_cast<int>(values.size()));
  for (std::size_t j = 0; j < values.size(); ++j) {
    const FitParameter& p = params[j];
    const double scale = values[j] != 0.0 ? std::abs(values[j]) : 0.5 * (p.upper - p.lower);
    double h = kJacobianStep * scale;
    if (values[j] + h > p.upper) h = -h;
    std::vector<double> moved = values;
    moved[j] += h;
    Prediction pm;
    if (!model.predict(moved, &pm)) {  // outside the term's validity that way: the other way
      h = -h;
      moved[j] = values[j] + h;
      if (!model.predict(moved, &pm))
        throw std::invalid_argument("numerics check: the model '" + label + "' cannot be evaluated near its fit");
    }
    for (int r = 0; r < m; ++r) {
      const auto [i, o] = rows.index[r];
      const Output out = static_cast<Output>(o);
      wj(r, static_cast<int>(j)) = (pm.value(out, i) - at.value(out, i)) / h / rows.sigma[r];
    }
  }
  return wj;
}

/// I - P, P the projector onto the columns of W J (rank-revealing: a parameter without effect on these runs
/// changes nothing).
Eigen::MatrixXd residualOperator(const Eigen::MatrixXd& wj) {
  const int m = static_cast<int>(wj.rows());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(wj);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(m, m);
  const Eigen::MatrixXd basis = q.leftCols(qr.rank());
  return Eigen::MatrixXd::Identity(m, m) - basis * basis.transpose();
}

/// The per-output summaries of the weighted solver error `wd` (d / sigma) against the preset's predictions.
void summarise(const Rows& rows, const Eigen::VectorXd& wd, const Prediction& at, NumericsCheck* c) {
  for (std::size_t r = 0; r < rows.index.size(); ++r) {
    const auto [i, o] = rows.index[r];
    NumericsOutput& s = c->outputs[o];
    ++s.values;
    s.noncentrality_raw += wd(static_cast<int>(r)) * wd(static_cast<int>(r));
    const double rel = wd(static_cast<int>(r)) * rows.sigma[r] / at.value(static_cast<Output>(o), i);
    s.rms_relative += rel * rel;
    s.max_relative = std::max(s.max_relative, std::abs(rel));
  }
  for (NumericsOutput& s : c->outputs)
    if (s.values > 0) {
      s.rms_in_noise = std::sqrt(s.noncentrality_raw / s.values);
      s.rms_relative = std::sqrt(s.rms_relative / s.values);
    }
}

/// Inclusion probabilities proportional to `importance` with expected sample size n; cells whose share would
/// exceed 1 are taken with certainty and the rest rescaled (the standard iteration).
std::vector<double> inclusionProbabilities(const std::vector<double>& importance, double n) {
  std::vector<double> pi(importance.size(), 0.0);
  std::vector<bool> certain(importance.size(), false);
  for (;;) {
    double rest = 0.0, left = n;
    for (std::size_t c = 0; c < importance.size(); ++c) {
      if (certain[c])
        left -= 1.0;
      else
        rest += importance[c];
    }
    bool changed = false;
    for (std::size_t c = 0; c < importance.size(); ++c) {
      if (certain[c]) continue;
      pi[c] = rest > 0.0 && left > 0.0 ? left * importance[c] / rest : 0.0;
      if (pi[c] >= 1.0) {
        certain[c] = true;
        changed = true;
      }
    }
    if (!changed) break;
  }
  for (std::size_t c = 0; c < pi.size(); ++c) pi[c] = certain[c] ? 1.0 : pi[c];
  return pi;
}

/// The `confidence` quantile of |A e|, e ~ N(0, S): |A e|^2 is a sum of weighted chi-squares with the eigenvalues
/// of A S A^T as weights.
double normQuantile(const Eigen::MatrixXd& a, const Eigen::MatrixXd& covariance, double confidence,
                    std::uint64_t seed) {
  const Eigen::MatrixXd m = a * covariance * a.transpose();
  const Eigen::VectorXd weights = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m).eigenvalues();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> z;
  std::vector<double> draws(kQuantileDraws);
  for (double& s : draws) {
    s = 0.0;
    for (int k = 0; k < weights.size(); ++k) {
      const double zk = z(rng);
      s += std::max(0.0, weights(k)) * zk * zk;
    }
  }
  const std::size_t at = std::min(draws.size() - 1, static_cast<std::size_t>(confidence * draws.size()));
  std::nth_element(draws.begin(), draws.begin() + static_cast<long>(at), draws.end());
  return std::sqrt(draws[at]);
}

/// The drive segments' weighted solver error from a growing Poisson sample of the coarse cells (file comment of
/// numerics_check.h); sets the interval and the decision in *c and returns the estimate d^ / sigma.
Eigen::VectorXd sampledSolverError(const ExtendedModel& preset, const ExtendedModel& finer,
                                   const std::vector<double>& values, const Rows& rows, const Eigen::MatrixXd& a,
                                   const NumericsSampling& sampling, NumericsCheck* c) {
  const int m = static_cast<int>(rows.index.size());
  std::vector<int> all(static_cast<std::size_t>(c->cells));
  for (int k = 0; k < c->cells; ++k) all[static_cast<std::size_t>(k)] = k;
  std::vector<std::vector<CellContribution>> at_preset;
  if (!preset.coarseCellContributions(values, all, &at_preset))
    throw std::invalid_argument("numerics check: the model '" + c->at_model + "' cannot be evaluated at its fit");
  // A cell's importance: its contribution to the weighted predictions of the measured values.
  auto weighted = [&](const std::vector<CellContribution>& contributions, Eigen::VectorXd* y) {
    for (const CellContribution& k : contributions)
      for (int o = 0; o < kNumOutputs; ++o) {
        const auto row = rows.row_of.find({k.run, o});
        if (row != rows.row_of.end())
          (*y)(row->second) += (o == 0 ? k.side_force_n : k.wear_kg_per_m) / rows.sigma[row->second];
      }
  };
  std::vector<double> importance(all.size());
  double total = 0.0;
  for (std::size_t k = 0; k < all.size(); ++k) {
    Eigen::VectorXd y = Eigen::VectorXd::Zero(m);
    weighted(at_preset[k], &y);
    importance[k] = y.cwiseAbs().sum();
    total += importance[k];
  }
  // Defensive mixture: a cell that the preset predicts to wear nothing (a low slip below its grid's first
  // sliding node) may wear at the finer preset, so every cell keeps a share of a uniform draw.
  for (double& x : importance) x = (1.0 - kUniformShare) * x / total + kUniformShare / importance.size();
  std::mt19937_64 rng(sampling.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> u(all.size());
  for (double& x : u) x = uniform(rng);
  std::map<int, Eigen::VectorXd> error_of;  // weighted solver error of each cell compared so far
  for (double n = sampling.first_sample_cells;; n *= kSampleGrowth) {
    // A sample as large as the cells takes every one (set exactly: the rescaling leaves some at 1 - 1e-16).
    const std::vector<double> pi =
        n >= c->cells ? std::vector<double>(importance.size(), 1.0) : inclusionProbabilities(importance, n);
    std::vector<int> sample, fresh;
    for (int k = 0; k < c->cells; ++k)
      if (u[static_cast<std::size_t>(k)] < pi[static_cast<std::size_t>(k)]) {
        sample.push_back(k);
        if (!error_of.count(k)) fresh.push_back(k);
      }
    std::vector<std::vector<CellContribution>> at_finer;
    if (!finer.coarseCellContributions(values, fresh, &at_finer))
      throw std::invalid_argument("numerics check: the model '" + c->at_model + "' cannot be evaluated at " +
                                  presetName(c->finer));
    for (std::size_t f = 0; f < fresh.size(); ++f) {
      Eigen::VectorXd y = Eigen::VectorXd::Zero(m), y_preset = Eigen::VectorXd::Zero(m);
      weighted(at_finer[f], &y);
      weighted(at_preset[static_cast<std::size_t>(fresh[f])], &y_preset);
      error_of[fresh[f]] = y - y_preset;
    }
    Eigen::VectorXd estimate = Eigen::VectorXd::Zero(m);
    Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(m, m);
    for (int k : sample) {
      const double p = pi[static_cast<std::size_t>(k)];
      const Eigen::VectorXd& y = error_of.at(k);
      estimate += y / p;
      covariance += (1.0 - p) / (p * p) * y * y.transpose();
    }
    c->cells_compared = static_cast<int>(error_of.size());
    const double root = (a * estimate).norm();
    const double q = normQuantile(a, covariance, sampling.confidence, sampling.seed + error_of.size());
    c->noncentrality = root * root;
    c->noncentrality_low = std::pow(std::max(0.0, root - q), 2);
    c->noncentrality_high = std::pow(root + q, 2);
    // Exact once every cell is in with certainty.
    const bool exact =
        static_cast<int>(sample.size()) == c->cells &&
        std::all_of(sample.begin(), sample.end(), [&](int k) { return pi[static_cast<std::size_t>(k)] >= 1.0; });
    c->sampled = !exact;
    c->confidence = exact ? 1.0 : sampling.confidence;
    if (exact || c->noncentrality_high <= c->limit || c->noncentrality_low > c->limit) {
      c->passed = exact ? c->noncentrality <= c->limit : c->noncentrality_high <= c->limit;
      return estimate;
    }
  }
}

}  // namespace

bool NumericsSampling::validate(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (first_sample_cells < 0)
    return fail("numerics_sampling.first_sample_cells = " + std::to_string(first_sample_cells) +
                " must be >= 0 (0: every cell)");
  if (!(confidence > 0.5 && confidence < 1.0))
    return fail("numerics_sampling.confidence = " + std::to_string(confidence) + " must be in (0.5, 1)");
  return true;
}

NumericsCheck checkNumerics(const TireParams& base, const DiagnosisData& data, const ExtendedModelOptions& options,
                            const std::vector<Term>& terms, const std::vector<double>& values,
                            const NoiseModel noise[kNumOutputs], double limit, const NumericsSampling& sampling) {
  const auto start = std::chrono::steady_clock::now();
  NumericsCheck c;
  c.at_model = termsLabel(terms);
  c.preset = options.preset;
  c.limit = limit;
  if (options.preset == Preset::kReference) return c;
  c.checked = true;
  ExtendedModelOptions preset_options = options;
  preset_options.coarse_cells_only = true;      // drive segments: the presets' difference on the coarse cells
  preset_options.interpolate_mu_scale = false;  // both presets evaluated at the fit itself, cell by cell
  const ExtendedModel coarse(base, preset_options, terms, data);
  ExtendedModelOptions finer_options = preset_options;
  finer_options.preset = c.finer;
  const ExtendedModel finer(base, finer_options, terms, data);
  c.cells = static_cast<int>(coarse.coarseCellCount());
  Prediction at;
  if (!coarse.predict(values, &at))
    throw std::invalid_argument("numerics check: the model '" + c.at_model + "' cannot be evaluated at its fit");
  const Rows rows = measuredRows(data, noise);
  const Eigen::MatrixXd a = residualOperator(weightedJacobian(coarse, values, at, rows, c.at_model));
  const bool all_drives =
      std::all_of(data.runs.begin(), data.runs.end(), [](const DiagnosisRun& r) { return r.isDrive(); });
  Eigen::VectorXd wd(static_cast<int>(rows.index.size()));
  if (all_drives && sampling.first_sample_cells > 0 && c.cells > sampling.first_sample_cells) {
    wd = sampledSolverError(coarse, finer, values, rows, a, sampling, &c);
  } else {
    Prediction ref;
    if (!finer.predict(values, &ref))
      throw std::invalid_argument("numerics check: the model '" + c.at_model + "' cannot be evaluated at its fit");
    for (std::size_t r = 0; r < rows.index.size(); ++r) {
      const auto [i, o] = rows.index[r];
      const Output out = static_cast<Output>(o);
      wd(static_cast<int>(r)) = (ref.value(out, i) - at.value(out, i)) / rows.sigma[r];
    }
    c.cells_compared = c.cells;
    c.noncentrality = (a * wd).squaredNorm();
    c.noncentrality_low = c.noncentrality_high = c.noncentrality;
    c.passed = c.noncentrality <= limit;
  }
  summarise(rows, wd, at, &c);
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return c;
}

std::string numericsSummary(const NumericsCheck& c) {
  if (!c.checked) return std::string("not checked at ") + presetName(c.preset) + " (the finest grid of the model)";
  char buf[600];
  int len = std::snprintf(buf, sizeof buf,
                          "solver error of %s against %s at '%s': lambda %.3g against the limit %.3g (side force "
                          "%.3g sigma RMS, %.3g%% RMS; wear %.3g sigma RMS, %.3g%% RMS)",
                          presetName(c.preset), presetName(c.finer), c.at_model.c_str(), c.noncentrality, c.limit,
                          c.outputs[0].rms_in_noise, 100.0 * c.outputs[0].rms_relative, c.outputs[1].rms_in_noise,
                          100.0 * c.outputs[1].rms_relative);
  if (c.sampled && len > 0 && len < static_cast<int>(sizeof buf))
    std::snprintf(buf + len, sizeof buf - len, ", estimated from %d of %d drive cells: %.3g-%.3g at %.0f%% confidence",
                  c.cells_compared, c.cells, c.noncentrality_low, c.noncentrality_high, 100.0 * c.confidence);
  return buf;
}

}  // namespace diagnosis
}  // namespace tread_wear
