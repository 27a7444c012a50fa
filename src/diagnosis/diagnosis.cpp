#include "tread_wear/diagnosis/diagnosis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "tread_wear/diagnosis/statistics.h"
#include "tread_wear/diagnosis/user_mechanisms.h"

namespace tread_wear {
namespace diagnosis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Noise-scale floors [-]: a relative residual weight below these would let a handful of near-identical
/// repeats dominate the fit (rig side force ~1 N on ~50 N is 2%; wear repeats scatter by several percent).
constexpr double kNoiseFloor[kNumOutputs] = {0.005, 0.01};
/// Noise scales [-] of the first base fit (the rig's typical 2% side force and 5% wear).
constexpr double kDefaultNoise[kNumOutputs] = {0.02, 0.05};
/// Error-ratio RMS [-] below which a model reproduces an output exactly. Noise-free generated recordings fitted
/// with the generating model leave residuals of ~1e-11 (the optimizer's convergence); any measurement leaves far
/// more. Below it, tests and fits would only see round-off: a trend in it is not a mismatch, and a term that
/// lowers it further (any term can) is not an explanation.
constexpr double kNumericalResolution = 1e-6;

/// Fewest measured runs of an output for its locating tests.
constexpr std::size_t kMinRunsToLocate = 6;

/// True when every measured output is reproduced to within kNumericalResolution.
bool reproducedExactly(const FittedModel& m) {
  for (int o = 0; o < kNumOutputs; ++o)
    if (std::isfinite(m.rmser[o]) && m.rmser[o] >= kNumericalResolution) return false;
  return true;
}

std::string format(double v, int precision = 4) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

class Fitter {
 public:
  Fitter(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options, const NoiseModel* noise)
      : base_(base), data_(data), options_(options) {
    setNoise(noise);
  }

  /// Fits base + terms, starting from `start` (values by parameter name) where given.
  FittedModel fit(const std::vector<Term>& terms, const std::map<std::string, double>& start, bool cross_validate) {
    ExtendedModel model(base_, options_.model, terms, data_);
    std::vector<FitParameter> params = model.parameters();
    for (FitParameter& p : params) {
      const auto it = start.find(p.name);
      if (it != start.end()) p.initial = std::clamp(it->second, p.lower, p.upper);
    }
    const std::vector<std::vector<FitParameter>> starts = model.fitStarts(params, start.count("t0_c") > 0);
    FittedModel best;
    bool have = false;
    for (const auto& s : starts) {
      LeastSquaresProblem problem = makeProblem(model, s);
      LeastSquaresSummary summary = solveLeastSquares(problem, options_.solver);
      if (!summary.usable) continue;
      if (!have || summary.final_cost < best.summary.final_cost) {
        best.summary = summary;
        have = true;
      }
    }
    best.terms = terms;
    best.label = termsLabel(terms);
    if (!have) return best;
    best.usable = true;
    best.k = static_cast<int>(params.size()) +
             (std::find(terms.begin(), terms.end(), Term::kTurnSlipOrientation) != terms.end() ? 1 : 0);
    model.predict(best.summary.values(), &best.prediction);
    best.rss = 0.0;
    best.n_residuals = 0;
    for (int o = 0; o < kNumOutputs; ++o) {
      const std::vector<double> y = relativeResiduals(data_, best.prediction, static_cast<Output>(o));
      double ss = 0.0;
      int m = 0;
      for (std::size_t i = 0; i < y.size(); ++i)
        if (std::isfinite(y[i])) {
          ss += y[i] * y[i];
          const double w =
              (best.prediction.value(static_cast<Output>(o), static_cast<int>(i)) - data_.runs[i].measured[o]) /
              sigma(i, o);
          best.rss += w * w;
          ++m;
        }
      best.rmser[o] = m > 0 ? std::sqrt(ss / m) : kNaN;
      best.n_residuals += m;
    }
    best.aicc = aicc(best.rss, best.n_residuals, best.k);
    best.bic = bic(best.rss, best.n_residuals, best.k);
    if (cross_validate) crossValidateModel(&best);
    return best;
  }

  /// Leave-one-group-out error of a fitted model, folds starting from its full-data solution.
  void crossValidateModel(FittedModel* fitted) {
    ExtendedModel model(base_, options_.model, fitted->terms, data_);
    std::vector<FitParameter> params = model.parameters();
    const std::vector<double> values = fitted->summary.values();
    for (std::size_t j = 0; j < params.size(); ++j)
      params[j].initial = std::clamp(values[j], params[j].lower, params[j].upper);
    LeastSquaresProblem problem = makeProblem(model, params);
    problem.groups = data_.cv_groups;
    CrossValidationResult cv = crossValidate(problem, options_.solver);
    if (!data_.cv_calibration_run.empty()) calibrateHeldOutWear(&cv);
    double ss[kNumOutputs] = {0.0, 0.0}, weighted = 0.0;
    int m[kNumOutputs] = {0, 0}, total = 0;
    fitted->cv_run_loss.assign(data_.runs.size(), kNaN);
    for (std::size_t i = 0; i < data_.runs.size(); ++i)
      for (int o = 0; o < kNumOutputs; ++o) {
        if (!std::isfinite(data_.runs[i].measured[o])) continue;
        const double r = cv.held_out_residuals[i * kNumOutputs + o];
        if (!std::isfinite(r)) continue;
        const double relative = r * sigma(i, o) / data_.runs[i].measured[o];
        ss[o] += relative * relative;
        weighted += r * r;
        double& run_loss = fitted->cv_run_loss[i];
        run_loss = (std::isfinite(run_loss) ? run_loss : 0.0) + r * r;
        ++m[o];
        ++total;
      }
    for (int o = 0; o < kNumOutputs; ++o) fitted->cv_rmser[o] = m[o] > 0 ? std::sqrt(ss[o] / m[o]) : kNaN;
    fitted->cv_score = total > 0 ? weighted / total : kNaN;
    fitted->cv_done = total > 0;
  }

 private:
  /// Each held-out group's wear predicted with its own wear scale c, fitted on its calibration runs (weighted least
  /// squares of c p against the measured m: c = sum p m / s^2 over sum p^2 / s^2); those runs leave the held-out
  /// wear residuals. The side force is predicted as fitted.
  void calibrateHeldOutWear(CrossValidationResult* cv) const {
    constexpr int o = static_cast<int>(Output::kWear);
    auto residual = [&](std::size_t run) -> double& { return cv->held_out_residuals[run * kNumOutputs + o]; };
    for (const CrossValidationFold& fold : cv->folds) {
      double pm = 0.0, pp = 0.0;
      for (int i : fold.held_out) {
        const auto run = static_cast<std::size_t>(i);
        if (!data_.cv_calibration_run[run] || !std::isfinite(residual(run))) continue;
        const double s = sigma(run, o), m = data_.runs[run].measured[o], p = residual(run) * s + m;
        pm += p * m / (s * s);
        pp += p * p / (s * s);
      }
      const double scale = pp > 0.0 ? pm / pp : kNaN;
      for (int i : fold.held_out) {
        const auto run = static_cast<std::size_t>(i);
        double& r = residual(run);
        if (data_.cv_calibration_run[run] || !std::isfinite(r)) {
          r = kNaN;
          continue;
        }
        const double s = sigma(run, o), m = data_.runs[run].measured[o];
        r = (scale * (r * s + m) - m) / s;
      }
    }
  }

  LeastSquaresProblem makeProblem(const ExtendedModel& model, const std::vector<FitParameter>& params) {
    LeastSquaresProblem problem;
    problem.parameters = params;
    problem.num_records = static_cast<int>(data_.runs.size());
    problem.residuals_per_record = kNumOutputs;
    const ExtendedModel* m = &model;
    problem.residuals = [this, m](const std::vector<double>& values, const std::vector<int>& records,
                                  double* residuals) {
      Prediction pred;
      if (!m->predict(values, &pred)) return false;
      for (std::size_t k = 0; k < records.size(); ++k) {
        const DiagnosisRun& run = data_.runs[records[k]];
        for (int o = 0; o < kNumOutputs; ++o) {
          const double meas = run.measured[o];
          residuals[k * kNumOutputs + o] =
              std::isfinite(meas) ? (pred.value(static_cast<Output>(o), records[k]) - meas) / sigma(records[k], o)
                                  : 0.0;
        }
      }
      return true;
    };
    return problem;
  }

  double sigma(std::size_t run, int output) const { return sigma_[run * kNumOutputs + output]; }

  const TireParams& base_;
  const DiagnosisData& data_;
  const DiagnosisOptions& options_;
  std::vector<double> sigma_;  ///< noise std per run and output at the measured value [unit of the output]

 public:
  void setNoise(const NoiseModel* noise) {
    sigma_.assign(data_.runs.size() * kNumOutputs, kNaN);
    for (std::size_t i = 0; i < data_.runs.size(); ++i)
      for (int o = 0; o < kNumOutputs; ++o)
        if (std::isfinite(data_.runs[i].measured[o]))
          sigma_[i * kNumOutputs + o] = noise[o].sigma(data_.runs[i].measured[o]);
  }
};

/// The repeats of output o as deviations for the noise model's selection (noise_model.h): a condition with n >= 2
/// measured runs and sum of squared deviations SS about its mean gives n - 1 values sqrt(SS / (n - 1)) at the level
/// of its mean (the likelihood of SS / sigma^2 ~ chi^2(n - 1) is that of n - 1 such values). False when the repeats
/// have fewer than kMinRepeatDof degrees of freedom or their levels span less than kMinLevelSpan.
bool repeatDeviations(const DiagnosisData& data, int o, std::vector<double>* e, std::vector<double>* y) {
  std::map<std::string, std::vector<double>> groups;
  for (const DiagnosisRun& r : data.runs)
    if (std::isfinite(r.measured[o])) groups[r.condition].push_back(r.measured[o]);
  e->clear();
  y->clear();
  double lo = INFINITY, hi = 0.0;
  for (const auto& [name, v] : groups) {
    if (v.size() < 2) continue;
    double mean = 0.0, ss = 0.0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    for (double x : v) ss += (x - mean) * (x - mean);
    const double dev = std::sqrt(ss / static_cast<double>(v.size() - 1));
    for (std::size_t k = 1; k < v.size(); ++k) {
      e->push_back(dev);
      y->push_back(mean);
    }
    lo = std::min(lo, std::abs(mean));
    hi = std::max(hi, std::abs(mean));
  }
  return static_cast<int>(e->size()) >= kMinRepeatDof && hi >= kMinLevelSpan * lo;
}

/// Pooled relative spread of repeats (runs sharing a condition) per output, and its degrees of freedom.
void pureError(const DiagnosisData& data, double* scale, int* dof) {
  for (int o = 0; o < kNumOutputs; ++o) {
    std::map<std::string, std::vector<double>> groups;
    for (const DiagnosisRun& r : data.runs)
      if (std::isfinite(r.measured[o])) groups[r.condition].push_back(r.measured[o]);
    double ss = 0.0;
    int d = 0;
    for (const auto& [name, v] : groups) {
      if (v.size() < 2) continue;
      double mean = 0.0;
      for (double x : v) mean += x;
      mean /= v.size();
      for (double x : v) ss += (x / mean - 1.0) * (x / mean - 1.0);
      d += static_cast<int>(v.size()) - 1;
    }
    dof[o] = d;
    scale[o] = d > 0 ? std::sqrt(ss / d) : kNaN;
  }
}

/// Largest minus smallest group mean of y (labels 0..G-1).
double largestGroupDifference(const std::vector<int>& labels, const std::vector<double>& y) {
  std::map<int, std::pair<double, int>> sums;
  for (std::size_t i = 0; i < y.size(); ++i) {
    sums[labels[i]].first += y[i];
    ++sums[labels[i]].second;
  }
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& [label, sum] : sums) {
    lo = std::min(lo, sum.first / sum.second);
    hi = std::max(hi, sum.first / sum.second);
  }
  return hi - lo;
}

/// Locating tests of both outputs' residuals of `model`; `not_tested` (if given) gets the outputs without tests
/// and why.
/// The tests rank the residuals standardised by the noise model, (predicted - measured) / sigma (for a relative
/// model the error ratios, scaled); slopes and group differences are reported in error-ratio points.
std::vector<LocatedEffect> locate(const DiagnosisData& data, const FittedModel& model, const NoiseModel* noise,
                                  const DiagnosisOptions& options, std::vector<std::string>* not_tested = nullptr) {
  const Prediction& prediction = model.prediction;
  std::vector<LocatedEffect> tests;
  std::uint64_t seed = options.seed;
  for (int o = 0; o < kNumOutputs; ++o) {
    const Output out = static_cast<Output>(o);
    const std::vector<double> res = relativeResiduals(data, prediction, out);
    std::vector<int> idx;
    for (std::size_t i = 0; i < res.size(); ++i)
      if (std::isfinite(res[i])) idx.push_back(static_cast<int>(i));
    auto skip = [&](const std::string& why) {
      if (not_tested) not_tested->push_back(std::string(outputName(out)) + ": " + why);
    };
    if (idx.size() < kMinRunsToLocate) {  // a trend test over fewer runs has no power
      skip(std::to_string(idx.size()) + " measured runs, the locating tests need " + std::to_string(kMinRunsToLocate));
      continue;
    }
    if (model.rmser[o] < kNumericalResolution) {
      skip("reproduced within numerical resolution, nothing to locate");
      continue;
    }
    std::vector<double> y, z;  // error ratios, standardised residuals
    for (int i : idx) {
      y.push_back(res[i]);
      const double meas = data.runs[i].measured[o];
      z.push_back((prediction.value(out, i) - meas) / noise[o].sigma(meas));
    }
    std::vector<Covariate> covariates = data.covariates;
    std::vector<double> level;
    for (std::size_t i = 0; i < data.runs.size(); ++i) level.push_back(prediction.value(out, static_cast<int>(i)));
    covariates.push_back({std::string("predicted_") + outputName(out), "output level", false, level, {}});
    for (const Covariate& c : covariates) {
      LocatedEffect e;
      e.output = out;
      e.covariate = c.name;
      e.kind = c.kind;
      e.categorical = c.categorical;
      ++seed;
      if (c.categorical) {
        std::vector<int> labels;
        std::map<int, int> remap;  // compact the levels present among the measured runs
        for (int i : idx) {
          const int l = static_cast<int>(c.values[i]);
          labels.push_back(remap.emplace(l, static_cast<int>(remap.size())).first->second);
        }
        if (remap.size() < 2 || remap.size() * 2 > idx.size()) continue;
        const GroupTest g = groupTest(labels, z, options.permutations, seed);
        e.eta_squared = g.eta_squared;
        e.effect = largestGroupDifference(labels, y);
        e.p_value = g.p_value;
      } else {
        std::vector<double> x;
        for (int i : idx) x.push_back(c.values[i]);
        if (std::adjacent_find(x.begin(), x.end(), std::not_equal_to<double>()) == x.end()) continue;
        const TrendTest t = trendTest(x, z, options.permutations, seed);
        e.rho = t.rho;
        e.slope = olsSlope(x, y);
        e.effect = e.slope * (*std::max_element(x.begin(), x.end()) - *std::min_element(x.begin(), x.end()));
        e.p_value = t.p_value;
      }
      tests.push_back(e);
    }
  }
  std::vector<double> p;
  for (const LocatedEffect& e : tests) p.push_back(e.p_value);
  const std::vector<double> adj = holmAdjust(p);
  for (std::size_t i = 0; i < tests.size(); ++i) {
    tests[i].p_adjusted = adj[i];
    tests[i].significant = adj[i] < options.alpha_locate;
  }
  std::stable_sort(tests.begin(), tests.end(),
                   [](const LocatedEffect& a, const LocatedEffect& b) { return a.p_value < b.p_value; });
  return tests;
}

std::map<std::string, double> valuesByName(const FittedModel& m) {
  std::map<std::string, double> v;
  for (const ParameterEstimate& p : m.summary.parameters) v[p.name] = p.value;
  return v;
}

/// One-sided Wilcoxon signed-rank p-value that `candidate` has lower held-out losses than `current`, paired by
/// run (runs held out by both). The runs' losses, not the folds', are the unit: a design has few folds (six
/// cycles), and ranks keep a few runs with large, heteroscedastic errors from deciding alone.
double heldOutImprovementPValue(const FittedModel& candidate, const FittedModel& current) {
  std::vector<double> differences;
  for (std::size_t i = 0; i < candidate.cv_run_loss.size() && i < current.cv_run_loss.size(); ++i) {
    const double d = candidate.cv_run_loss[i] - current.cv_run_loss[i];
    if (std::isfinite(d)) differences.push_back(d);
  }
  return wilcoxonSignedRankPValue(differences);
}

/// Partial F test of `f` (the parent plus `added`) against the parent. A term with one parameter whose no-effect
/// value is a bound (a polishing rate, a compliance, a load-std scale: none can be negative) gets the boundary
/// version while its estimate is off the bound; on the bound the RSS is the parent's and the plain p (~1) stands.
double pValueVsParent(const FittedModel& parent, const FittedModel& f, Term added) {
  const int dof = f.n_residuals - f.k;
  const TermInfo& info = termInfo(added);
  if (neutralOnBound(info)) {
    const std::string& name = info.parameters.front().name;
    for (const ParameterEstimate& p : f.summary.parameters)
      if (p.name == name && !p.atBound()) return nestedFTestPValueOnBound(parent.rss, f.rss, dof);
  }
  return nestedFTestPValue(parent.rss, f.rss, std::max(1, f.k - parent.k), dof);
}

/// The noise a fitted model leaves, as detection_limits.h measures it: side force in N, wear relative; root mean
/// squares scaled by sqrt(n / (n - k)) for the k fitted parameters, floored like the weights (side force relative
/// to its RMS level). NaN for an output that is not measured.
void estimateNoise(const DiagnosisData& data, const FittedModel& model, double* side_force_n, double* wear_rsd) {
  double sum_sq[kNumOutputs] = {0.0, 0.0}, level_sq = 0.0;
  int n[kNumOutputs] = {0, 0};
  for (std::size_t i = 0; i < data.runs.size(); ++i)
    for (int o = 0; o < kNumOutputs; ++o) {
      const double meas = data.runs[i].measured[o];
      if (!std::isfinite(meas)) continue;
      const double pred = model.prediction.value(static_cast<Output>(o), static_cast<int>(i));
      const bool force = o == static_cast<int>(Output::kSideForce);
      const double e = force ? pred - meas : pred / meas - 1.0;
      sum_sq[o] += e * e;
      if (force) level_sq += meas * meas;
      ++n[o];
    }
  const int total = n[0] + n[1];
  const double dof = total > model.k ? static_cast<double>(total) / (total - model.k) : 1.0;
  double* out[kNumOutputs] = {side_force_n, wear_rsd};
  for (int o = 0; o < kNumOutputs; ++o) {
    if (n[o] == 0) {
      *out[o] = kNaN;
      continue;
    }
    const double level = o == static_cast<int>(Output::kSideForce) ? std::sqrt(level_sq / n[o]) : 1.0;
    *out[o] = std::max(std::sqrt(sum_sq[o] / n[o] * dof), kNoiseFloor[o] * level);
  }
}

}  // namespace

DiagnosisOptions::DiagnosisOptions() {
  solver.max_iterations = 60;
  solver.function_tolerance = 1e-8;
  solver.parameter_tolerance = 1e-8;
  solver.gradient_tolerance = 1e-10;
  // Error ratios of a transducer with additive noise vary in variance from run to run (about 3x between the 5 and
  // 15 deg runs of the rig program); the sandwich keeps the reported uncertainties of the terms that the noisier
  // runs decide (gain, offset) honest.
  solver.robust_covariance = true;
  // The brush model is solved on a fixed grid: a step of 1e-4 in the internal coordinate keeps the finite
  // differences well above its discretisation noise.
  solver.jacobian_step = 1e-4;
  // A Jacobian re-simulates every coarse drive cell twice per brush parameter, and the line search of a bounded
  // step takes one at every trial (on 12 drives 61 of a pressure_friction fit's 69 Jacobians came from it).
  solver.bounded_line_search = false;
  // Wear alone hardly fixes friction: mu_scale often ends on its bound (3), where Ceres's projected steps crawl.
  solver.hold_bound_parameters = true;
}

bool DiagnosisOptions::validate(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "diagnosis options: " + m;
    return false;
  };
  if (!(alpha_locate > 0.0 && alpha_locate < 1.0))
    return fail("alpha_locate = " + format(alpha_locate) + " must be in (0, 1)");
  if (!(alpha_select > 0.0 && alpha_select < 1.0))
    return fail("alpha_select = " + format(alpha_select) + " must be in (0, 1)");
  if (!(min_aicc_drop >= 0.0)) return fail("min_aicc_drop = " + format(min_aicc_drop) + " must be >= 0");
  if (max_terms < 0) return fail("max_terms = " + std::to_string(max_terms) + " must be >= 0");
  if (max_cv_candidates < 1) return fail("max_cv_candidates = " + std::to_string(max_cv_candidates) + " must be >= 1");
  if (permutations < 99) return fail("permutations = " + std::to_string(permutations) + " must be >= 99");
  if (!(numerics_limit > 0.0) || !std::isfinite(numerics_limit))
    return fail("numerics_limit = " + format(numerics_limit) + " must be finite and > 0");
  if (auto_preset && max_auto_preset < model.preset)
    return fail(std::string("max_auto_preset = ") + presetName(max_auto_preset) +
                " must be at least model.preset = " + presetName(model.preset));
  if (!(detection_power >= 0.0 && detection_power < 1.0))
    return fail("detection_power = " + format(detection_power) + " must be in (0, 1), or 0 for none");
  if (model.jobs < 1) return fail("model.jobs = " + std::to_string(model.jobs) + " must be >= 1");
  std::string e;
  if (!numerics_sampling.validate(&e)) return fail(e);
  if (!solver.validate(&e)) return fail(e);
  return true;
}

std::vector<double> relativeResiduals(const DiagnosisData& data, const Prediction& prediction, Output output) {
  std::vector<double> r(data.runs.size(), kNaN);
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    const double meas = data.runs[i].measured[static_cast<int>(output)];
    if (std::isfinite(meas)) r[i] = prediction.value(output, static_cast<int>(i)) / meas - 1.0;
  }
  return r;
}

double fittedValue(const FittedModel& model, const std::string& name, double* std_error) {
  for (const ParameterEstimate& p : model.summary.parameters)
    if (p.name == name) {
      if (std_error) *std_error = p.std_error;
      return p.value;
    }
  if (std_error) *std_error = kNaN;
  return kNaN;
}

DetectabilityOptions detectabilityOptions(const DiagnosisOptions& diagnosis, double wear_noise_rsd,
                                          double side_force_noise_n) {
  DetectabilityOptions d;
  d.wear_noise_rsd = wear_noise_rsd;
  d.side_force_noise_n = side_force_noise_n;
  d.alpha_select = diagnosis.alpha_select;
  d.min_aicc_drop = diagnosis.min_aicc_drop;
  d.candidates = diagnosis.candidates;
  d.model = diagnosis.model;
  d.solver = diagnosis.solver;
  return d;
}

namespace {

/// The noise model of output o as selected (or given) on the repeats, else on the residuals of the fitted model.
NoiseSelection noiseSelection(const DiagnosisData& data, const FittedModel& fitted, int o,
                              const std::optional<NoiseKind>& given) {
  std::vector<double> e, y;
  std::string source;
  if (repeatDeviations(data, o, &e, &y)) {
    source = "repeats (" + std::to_string(e.size()) + " degrees of freedom)";
  } else {
    for (std::size_t i = 0; i < data.runs.size(); ++i) {
      const double meas = data.runs[i].measured[o];
      if (!std::isfinite(meas)) continue;
      e.push_back(fitted.prediction.value(static_cast<Output>(o), static_cast<int>(i)) - meas);
      y.push_back(meas);
    }
    source = "base-model residuals (" + std::to_string(e.size()) + " values)";
  }
  NoiseSelection s;
  if (e.size() < 3) {  // too few to estimate: the relative model (the error ratios), sized by the residuals
    s.model.relative = 1.0;
    s.source = "too few values (" + std::to_string(e.size()) + "): relative";
    return s;
  }
  s = given ? fitNoiseModel(*given, e, y) : selectNoiseModel(e, y);
  s.source = source;
  if (!(s.model.additive > 0.0 || s.model.relative > 0.0)) {  // exact values (noise-free): no size to select on
    s.model = NoiseModel{};
    s.model.relative = 1.0;
    s.source += ", reproduced exactly: relative";
  }
  return s;
}

/// `shape` sized to the residuals of `fitted` (its weighted RMS is then 1), floored so that the RMS of sigma/|y|
/// over the measured runs is at least kNoiseFloor.
NoiseModel sizedNoise(const DiagnosisData& data, const FittedModel& fitted, const NoiseModel& shape, int o) {
  double ss = 0.0, rel = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    const double meas = data.runs[i].measured[o];
    if (!std::isfinite(meas)) continue;
    const double sigma = shape.sigma(meas);
    const double w = (fitted.prediction.value(static_cast<Output>(o), static_cast<int>(i)) - meas) / sigma;
    ss += w * w;
    rel += sigma * sigma / (meas * meas);
    ++n;
  }
  if (n == 0) return shape;
  const double factor = std::sqrt(ss / n), relative_rms = std::sqrt(rel / n);
  return shape.scaled(std::max(factor, kNoiseFloor[o] / relative_rms));
}

/// Times the steps of a diagnosis (DiagnosisResult::timings) and reports where it is (DiagnosisOptions::progress).
class StepClock {
 public:
  using Clock = std::chrono::steady_clock;
  explicit StepClock(const DiagnosisOptions& options)
      : options_(options), start_(Clock::now()), cells_at_start_(cellsEvaluated().load()) {}

  void setPreset(Preset preset) { preset_ = preset; }
  /// Starts a step; terms_in_step > 0 for a selection step (its progress then counts the terms fitted).
  void begin(const std::string& step, int terms_in_step = 0) {
    step_ = step;
    step_start_ = Clock::now();
    cells_at_step_ = cellsEvaluated().load();
    terms_in_step_ = terms_in_step;
    terms_tried_ = 0;
    report(-1.0);
  }
  /// A term of the current selection step is fitted: the time left is the mean time per term so far times the
  /// terms still to fit (the cross-validation of the eligible ones comes on top).
  void termTried() {
    ++terms_tried_;
    const double in_step = seconds(step_start_);
    report(in_step / terms_tried_ * (terms_in_step_ - terms_tried_));
  }
  /// Ends the current step into `timings`.
  void end(std::vector<StepTiming>* timings) const {
    timings->push_back({step_, preset_, seconds(step_start_), cellsEvaluated().load() - cells_at_step_});
  }
  double elapsed() const { return seconds(start_); }

 private:
  static double seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }
  void report(double step_left_s) const {
    if (!options_.progress) return;
    DiagnosisProgress p;
    p.step = step_;
    p.preset = preset_;
    p.cells_evaluated = cellsEvaluated().load() - cells_at_start_;
    p.terms_tried = terms_tried_;
    p.terms_in_step = terms_in_step_;
    p.elapsed_s = elapsed();
    p.step_left_s = step_left_s;
    options_.progress(p);
  }

  const DiagnosisOptions& options_;
  Clock::time_point start_, step_start_;
  long cells_at_start_ = 0, cells_at_step_ = 0;
  Preset preset_ = Preset::kFast;
  std::string step_;
  int terms_in_step_ = 0, terms_tried_ = 0;
};

/// Step 4, forward selection from the base model over the applicable terms: each step fits every term not yet in
/// the model, cross-validates the eligible ones and accepts the best if it is better out of sample (the pair step
/// significantly so). Returns the final model; the models tried, the log and the close alternatives go into
/// *result.
FittedModel forwardSelection(Fitter& fitter, const std::vector<Term>& applicable, const DiagnosisOptions& options,
                             const std::function<FittedModel(const FittedModel&)>& reweight, StepClock& clock,
                             DiagnosisResult* result_out) {
  DiagnosisResult& result = *result_out;
  FittedModel current = result.base;
  for (int step = 0; step < options.max_terms; ++step) {
    if (reproducedExactly(current)) {
      result.log.push_back("step " + std::to_string(step + 1) + " from '" + current.label +
                           "': every output reproduced within numerical resolution (RMSER < " +
                           format(kNumericalResolution) + "): stop");
      break;
    }
    int to_fit = 0;
    for (Term t : applicable) to_fit += std::find(current.terms.begin(), current.terms.end(), t) == current.terms.end();
    clock.begin("selection step " + std::to_string(step + 1), to_fit);
    std::vector<FittedModel> fits;
    for (Term t : applicable) {
      if (std::find(current.terms.begin(), current.terms.end(), t) != current.terms.end()) continue;
      std::vector<Term> terms = current.terms;
      terms.push_back(t);
      FittedModel f = fitter.fit(terms, valuesByName(current), false);
      f.parent = current.label;
      if (f.usable) f.p_vs_parent = pValueVsParent(current, f, t);
      fits.push_back(std::move(f));
      clock.termTried();
    }
    if (fits.empty()) {
      clock.end(&result.timings);
      break;
    }
    const double threshold = options.alpha_select / static_cast<double>(fits.size());
    std::vector<int> eligible;
    for (std::size_t i = 0; i < fits.size(); ++i) {
      FittedModel& f = fits[i];
      f.eligible = f.usable && f.p_vs_parent < threshold && current.aicc - f.aicc >= options.min_aicc_drop;
      if (f.eligible) eligible.push_back(static_cast<int>(i));
    }
    std::sort(eligible.begin(), eligible.end(), [&](int a, int b) { return fits[a].aicc < fits[b].aicc; });
    if (static_cast<int>(eligible.size()) > options.max_cv_candidates) eligible.resize(options.max_cv_candidates);
    int best = -1;
    for (int i : eligible) {
      fitter.crossValidateModel(&fits[i]);
      if (fits[i].cv_done && (best < 0 || fits[i].cv_score < fits[best].cv_score)) best = i;
    }
    std::ostringstream line;
    line << "step " << step + 1 << " from '" << current.label << "': " << fits.size() << " terms tried, "
         << eligible.size() << " eligible (F test p < " << format(threshold, 3)
         << ", AICc drop >= " << options.min_aicc_drop << ")";
    const bool better = best >= 0 && fits[best].cv_score < current.cv_score;
    bool accept = better;
    if (best >= 0)
      line << "; best held out: " << fits[best].label << " (score " << format(fits[best].cv_score) << " vs "
           << format(current.cv_score) << ")";
    if (better && !current.terms.empty()) {
      // Extending an explanation: what is left after the first term is near the noise, where the F test's
      // equal-variance assumption fails first (error ratios of an additive transducer noise), so the held-out
      // improvement must be significant, not merely present. The first term keeps the plain comparison: a
      // physical effect often shows in only a few conditions of a design (slip angle, load), which a rank test
      // over all runs would miss.
      fits[best].p_held_out = heldOutImprovementPValue(fits[best], current);
      accept = fits[best].p_held_out < options.alpha_select;
      line << ", held-out improvement over runs p = " << format(fits[best].p_held_out, 3) << " (Wilcoxon, < "
           << options.alpha_select << (accept ? ")" : " needed)");
    }
    if (best < 0)
      line << ": stop";
    else if (!better)
      line << ", not better out of sample: stop";
    else
      line << (accept ? ", accepted" : ": stop");
    result.log.push_back(line.str());
    if (accept)
      for (int i : eligible) {
        const double delta = fits[i].aicc - fits[best].aicc;
        if (i != best && delta < options.min_aicc_drop)
          result.close_alternatives.push_back({fits[i].label, fits[best].label, delta});
      }
    for (FittedModel& f : fits) result.tried.push_back(f);
    if (accept) current = reweight(fits[best]);
    clock.end(&result.timings);
    if (!accept) break;
  }
  return current;
}

/// Step 1's start: the relative model at the rig's typical size for the first base fit, and the repeats' relative
/// pure error, reported beside.
void startWeights(const DiagnosisData& data, DiagnosisResult* result) {
  double pe[kNumOutputs];
  int dof[kNumOutputs];
  pureError(data, pe, dof);
  for (int o = 0; o < kNumOutputs; ++o) {
    result->pure_error[o] = pe[o];
    result->pure_error_dof[o] = dof[o];
    result->weights[o].relative = kDefaultNoise[o];
  }
}

/// Step 4's pool: the candidates (each once: a repeat would be fitted twice and count twice in Bonferroni; none
/// given: the whole library) that the data can show; the others go to skipped_terms with the reason. A user term
/// must leave the model as it is at its no-effect values (checkNoEffect throws otherwise).
std::vector<Term> applicableTerms(const DiagnosisData& data, const DiagnosisOptions& options, DiagnosisResult* result) {
  std::vector<Term> pool;
  for (Term t : options.candidates)
    if (std::find(pool.begin(), pool.end(), t) == pool.end()) pool.push_back(t);
  if (pool.empty())
    for (const TermInfo& t : termLibrary()) pool.push_back(t.term);
  std::vector<Term> applicable;
  for (Term t : pool) {
    std::string why;
    if (termApplicable(t, data, &why))
      applicable.push_back(t);
    else
      result->skipped_terms.push_back(termInfo(t).name + ": " + why);
  }
  for (Term t : applicable)
    if (termInfo(t).user) checkNoEffect(termInfo(t), data, result->base.prediction);
  return applicable;
}

/// Step 5: the accepted terms, else "unexplained" with the covariates the residual follows when a locating test was
/// significant, else "none".
void setVerdict(const FittedModel& current, DiagnosisResult* result) {
  const bool located = std::any_of(result->located_before.begin(), result->located_before.end(),
                                   [](const LocatedEffect& e) { return e.significant; });
  if (!current.terms.empty()) {
    result->explanation = current.label;
  } else if (located) {
    result->explanation = "unexplained";
    std::set<std::string> seen;
    for (const LocatedEffect& e : result->located_before)
      if (e.significant && seen.insert(e.covariate).second) result->unexplained_covariates.push_back(e.covariate);
  } else {
    result->explanation = "none";
  }
  result->mismatch_found = result->explanation != "none";
}

/// Step 6: the noise the final model leaves and, with detection_power > 0, the detection limits at it.
void detectionLimitsStep(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options,
                         const FittedModel& current, StepClock& clock, DiagnosisResult* result) {
  estimateNoise(data, current, &result->side_force_noise_n, &result->wear_noise_rsd);
  if (!(options.detection_power > 0.0)) return;
  // An output that is not measured has no residuals to weigh; any positive noise level will do.
  const DetectabilityOptions d =
      detectabilityOptions(options, std::isfinite(result->wear_noise_rsd) ? result->wear_noise_rsd : 1.0,
                           std::isfinite(result->side_force_noise_n) ? result->side_force_noise_n : 1.0);
  result->detection_power = options.detection_power;
  clock.begin("detection limits");
  result->detection_limits = detectionLimits(base, data, fittedValue(result->base, "w3_scale"),
                                             fittedValue(result->base, "mu_scale"), options.detection_power, d);
  clock.end(&result->timings);
}

/// Runs steps 1-6 at options.model.preset, with the numerics check (step 0) at the base fit and at the final
/// model; with `stop_on_failed_check`, returns right after a failed check at the base fit.
DiagnosisResult diagnoseAtPreset(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options,
                                 bool stop_on_failed_check, StepClock& clock) {
  DiagnosisResult result;
  clock.setPreset(options.model.preset);
  result.preset = options.model.preset;
  result.cv_scheme = data.cv_scheme;

  // 1. Weights: see startWeights; then each output's noise model, sized to the current model's residuals.
  startWeights(data, &result);
  Fitter fitter(base, data, options, result.weights);
  auto reweight = [&](const FittedModel& m) {
    for (int o = 0; o < kNumOutputs; ++o)
      if (std::isfinite(m.rmser[o])) result.weights[o] = sizedNoise(data, m, result.noise[o].model, o);
    fitter.setNoise(result.weights);
    return fitter.fit(m.terms, valuesByName(m), true);
  };
  auto check = [&](const FittedModel& m) {
    clock.begin("numerics check at '" + m.label + "'");
    result.numerics.push_back(checkNumerics(base, data, options.model, m.terms, m.summary.values(), result.weights,
                                            options.numerics_limit, options.numerics_sampling));
    clock.end(&result.timings);
    return result.numerics.back().passed;
  };

  // 2. Base fit, then again with the noise models sized by its residuals.
  clock.begin("base fit");
  result.base = fitter.fit({}, {}, false);
  if (!result.base.usable)
    throw std::invalid_argument("the base model could not be fitted: " + result.base.summary.message);
  for (int o = 0; o < kNumOutputs; ++o) result.noise[o] = noiseSelection(data, result.base, o, options.noise_kind[o]);
  result.base = reweight(result.base);
  clock.end(&result.timings);
  if (!check(result.base) && stop_on_failed_check) return result;

  // 3. Locate.
  clock.begin("locate");
  result.located_before = locate(data, result.base, result.weights, options, &result.not_located);
  clock.end(&result.timings);

  // 4. Explain: forward selection.
  const std::vector<Term> applicable = applicableTerms(data, options, &result);
  const FittedModel current = forwardSelection(fitter, applicable, options, reweight, clock, &result);
  result.final_model = current;
  clock.begin("locate after");
  result.located_after = locate(data, current, result.weights, options, &result.not_located_after);
  clock.end(&result.timings);
  if (!current.terms.empty()) check(current);

  // 5. Verdict, with the empirical terms after "unexplained".
  setVerdict(current, &result);
  if (options.empirical && result.explanation == "unexplained") {
    clock.begin("empirical terms");
    result.empirical = fitEmpiricalTerms(base, data, options, result);
    clock.end(&result.timings);
  }

  // 6. Detection limits at the noise the final model leaves.
  detectionLimitsStep(base, data, options, current, clock, &result);
  return result;
}

Preset finerPreset(Preset p) { return static_cast<Preset>(static_cast<int>(p) + 1); }

}  // namespace

DiagnosisResult diagnose(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options) {
  std::string error;
  if (!options.validate(&error)) throw std::invalid_argument(error);
  if (!base.validate(&error)) throw std::invalid_argument(error);
  DiagnosisOptions at = options;
  std::vector<NumericsCheck> checks;
  std::vector<StepTiming> timings;
  StepClock clock(options);
  std::string path = presetName(options.model.preset);
  for (;;) {
    DiagnosisResult r = diagnoseAtPreset(base, data, at, options.auto_preset, clock);
    const NumericsCheck last = r.numerics.back();
    checks.insert(checks.end(), r.numerics.begin(), r.numerics.end());
    timings.insert(timings.end(), r.timings.begin(), r.timings.end());
    const bool passed =
        std::all_of(r.numerics.begin(), r.numerics.end(), [](const NumericsCheck& c) { return c.passed; });
    if (passed || !options.auto_preset) {
      r.numerics = checks;
      r.timings = timings;
      r.seconds = clock.elapsed();
      if (!options.auto_preset) {
        r.numerics_decision =
            std::string("preset ") + presetName(at.model.preset) + " (given): " +
            (passed ? "solver error small against the noise" : "solver error NOT small against the noise") + "; " +
            numericsSummary(last);
        if (!passed)
          r.numerics_warning = std::string("the solver error of preset ") + presetName(at.model.preset) +
                               " is not small against the measurement noise (" + numericsSummary(last) +
                               "): the verdict may mistake numerics for physics; a finer --preset (or auto) is advised";
      } else if (path == presetName(at.model.preset)) {
        r.numerics_decision = "preset " + path + " kept: " + numericsSummary(last);
      } else {
        r.numerics_decision = "preset escalated " + path + ": " + numericsSummary(last);
      }
      return r;
    }
    if (at.model.preset >= options.max_auto_preset)
      throw DiagnosisError(std::string("the solver error is too large against the measurement noise even at preset ") +
                           presetName(at.model.preset) + " (the finest the diagnosis chooses; escalated " + path +
                           "): " + numericsSummary(last) +
                           ". The verdict would mistake numerics for physics; refusing. A diagnosis at a finer preset "
                           "(--preset reference) is possible but slow.");
    at.model.preset = finerPreset(at.model.preset);
    char why[160];
    std::snprintf(why, sizeof why, " (lambda %.3g > %.3g at '%s')", last.noncentrality, last.limit,
                  last.at_model.c_str());
    path += why + std::string(" -> ") + presetName(at.model.preset);
  }
}

}  // namespace diagnosis
}  // namespace tread_wear
