#include "tread_wear/diagnosis/detection_limits.h"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/non_central_f.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>

#include "tread_wear/diagnosis/statistics.h"

namespace tread_wear {
namespace diagnosis {
namespace {

/// Noncentrality above which the power is 1 to double precision for any level used here.
constexpr double kCertainLambda = 1e4;
/// Finite-difference step of the Jacobians, relative to the parameter's scale [-].
constexpr double kJacobianStep = 1e-5;

class Linearisation {
 public:
  Linearisation(const TireParams& base, const DiagnosisData& truth, const DetectabilityOptions& options)
      : base_(base), truth_(truth), options_(options) {
    for (std::size_t i = 0; i < truth.runs.size(); ++i)
      for (int o = 0; o < kNumOutputs; ++o)
        if (std::isfinite(truth.runs[i].measured[o])) rows_.push_back({static_cast<int>(i), o});
  }

  int measured() const { return static_cast<int>(rows_.size()); }

  /// The model's least-squares fit to the truth in noise units (the best of its starts); unusable if none converged.
  LeastSquaresSummary bestFit(const ExtendedModel& model) const {
    LeastSquaresProblem problem;
    problem.num_records = static_cast<int>(truth_.runs.size());
    problem.residuals_per_record = kNumOutputs;
    problem.residuals = [&](const std::vector<double>& values, const std::vector<int>& records, double* out) {
      Prediction pred;
      if (!model.predict(values, &pred)) return false;
      for (std::size_t k = 0; k < records.size(); ++k)
        for (int o = 0; o < kNumOutputs; ++o) out[k * kNumOutputs + o] = residual(pred, records[k], o);
      return true;
    };
    LeastSquaresSummary best;
    for (const std::vector<FitParameter>& start : model.fitStarts(model.parameters(), false)) {
      problem.parameters = start;
      LeastSquaresSummary s = solveLeastSquares(problem, options_.solver);
      if (s.usable && (!best.usable || s.final_cost < best.final_cost)) best = std::move(s);
    }
    return best;
  }

  /// lambda of Detectability: the base model's smallest residual sum of squares on the truth, in noise units.
  double baseLambda() const {
    const LeastSquaresSummary best = bestFit(ExtendedModel(base_, options_.model, {}, truth_));
    if (!best.usable) throw std::invalid_argument("detectability: the base model cannot be fitted to the truth");
    return 2.0 * best.final_cost;
  }

  LinearisedModel fit(const std::vector<Term>& terms) const {
    LinearisedModel m;
    m.terms = terms;
    m.k = parameterCount(terms);
    const ExtendedModel model(base_, options_.model, terms, truth_);
    const LeastSquaresSummary best = bestFit(model);
    if (!best.usable) return m;
    const std::vector<double> values = best.values();
    Eigen::VectorXd r0;
    if (!residualVector(model, values, &r0)) return m;
    // Jacobian columns of the parameters off their bounds; forward differences inwards from a bound.
    const std::vector<FitParameter> params = model.parameters();
    std::vector<Eigen::VectorXd> columns;
    std::vector<bool> lower_bound;
    std::vector<int> column_parameter;
    for (std::size_t j = 0; j < values.size(); ++j) {
      const ParameterEstimate& est = best.parameters[j];
      if (est.at_upper) continue;  // an effect driven to its upper bound: held there (rare; conservative)
      const double h = kJacobianStep * std::max({std::abs(values[j]), std::abs(params[j].initial), 1e-12});
      std::vector<double> up = values, down = values;
      up[j] += h;
      down[j] -= est.at_lower ? 0.0 : h;
      Eigen::VectorXd r_up, r_down;
      if (!residualVector(model, up, &r_up) || !residualVector(model, down, &r_down)) return m;
      columns.push_back((r_up - r_down) / (up[j] - down[j]));
      lower_bound.push_back(est.at_lower);
      column_parameter.push_back(static_cast<int>(j));
    }
    Eigen::MatrixXd jacobian(measured(), static_cast<int>(columns.size()));
    for (std::size_t j = 0; j < columns.size(); ++j) jacobian.col(j) = columns[j];
    m.residual = r0;
    m.basis = thinQ(jacobian);
    m.pseudo_inverse = jacobian.completeOrthogonalDecomposition().pseudoInverse();
    // Unit noise: the covariance of the parameter step is pinv pinv^T.
    for (std::size_t j = 0; j < values.size(); ++j)
      m.parameters.push_back({params[j].name, values[j], std::numeric_limits<double>::quiet_NaN()});
    for (std::size_t c = 0; c < column_parameter.size(); ++c)
      if (!lower_bound[c]) m.parameters[column_parameter[c]].std_error = m.pseudo_inverse.row(c).norm();
    // Parameters on their lower bound: one may move inwards (one_sided); several are held there.
    const int bounded = static_cast<int>(std::count(lower_bound.begin(), lower_bound.end(), true));
    if (bounded > 0) {
      Eigen::MatrixXd free_columns(jacobian.rows(), jacobian.cols() - bounded);
      for (int j = 0, c = 0; j < jacobian.cols(); ++j)
        if (!lower_bound[j]) free_columns.col(c++) = jacobian.col(j);
      if (bounded == 1) {
        m.one_sided = static_cast<int>(std::find(lower_bound.begin(), lower_bound.end(), true) - lower_bound.begin());
        m.basis_without = thinQ(free_columns);
      } else {
        m.basis = thinQ(free_columns);
      }
    }
    m.usable = true;
    return m;
  }

 private:
  struct Row {
    int run, output;
  };

  double residual(const Prediction& pred, int run, int output) const {
    const double meas = truth_.runs[run].measured[output];
    if (!std::isfinite(meas)) return 0.0;
    return output == static_cast<int>(Output::kSideForce)
               ? (pred.side_force_n[run] - meas) / options_.side_force_noise_n
               : (pred.wear_kg_per_m[run] / meas - 1.0) / options_.wear_noise_rsd;
  }

  bool residualVector(const ExtendedModel& model, const std::vector<double>& values, Eigen::VectorXd* out) const {
    Prediction pred;
    if (!model.predict(values, &pred)) return false;
    out->resize(measured());
    for (int i = 0; i < measured(); ++i) (*out)(i) = residual(pred, rows_[i].run, rows_[i].output);
    return true;
  }

  static Eigen::MatrixXd thinQ(const Eigen::MatrixXd& a) {
    if (a.cols() == 0) return Eigen::MatrixXd(a.rows(), 0);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
    return qr.householderQ() * Eigen::MatrixXd::Identity(a.rows(), a.cols());
  }

  const TireParams& base_;
  const DiagnosisData& truth_;
  const DetectabilityOptions& options_;
  std::vector<Row> rows_;
};

}  // namespace

/// Parameters of base + terms: the two levels, the terms' parameters, and the orientation switch counted as one
/// (as the diagnosis's AICc does).
int parameterCount(const std::vector<Term>& terms) {
  int p = 2;
  for (Term t : terms) p += static_cast<int>(termInfo(t).parameters.size()) + (t == Term::kTurnSlipOrientation);
  return p;
}

/// Whether the options ask for the term (no candidates: every term).
bool candidateWanted(const DetectabilityOptions& options, Term term) {
  return options.candidates.empty() ||
         std::find(options.candidates.begin(), options.candidates.end(), term) != options.candidates.end();
}

/// Level of the first-step F test of a term among `terms_tried` (Bonferroni), doubled for a term whose no-effect
/// value is a bound (the boundary test: p / 2 < level while the estimate is off the bound).
double firstStepLevel(Term term, double alpha_select, int terms_tried) {
  const double level = alpha_select / std::max(1, terms_tried);
  return neutralOnBound(termInfo(term)) ? 2.0 * level : level;
}

/// Measured values of the recordings (side force and wear, where recorded).
int measuredValues(const DiagnosisData& data) {
  int n = 0;
  for (const DiagnosisRun& r : data.runs)
    for (int o = 0; o < kNumOutputs; ++o) n += std::isfinite(r.measured[o]) ? 1 : 0;
  return n;
}

double fCritical(double df1, double df2, double level) {
  return boost::math::quantile(boost::math::complement(boost::math::fisher_f(df1, df2), level));
}

LinearisedModel linearisedFit(const TireParams& base, const DiagnosisData& truth, const DetectabilityOptions& options,
                              const std::vector<Term>& terms) {
  return Linearisation(base, truth, options).fit(terms);
}

bool DetectabilityOptions::validate(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "detectability options: " + m;
    return false;
  };
  if (!(wear_noise_rsd > 0.0) || !std::isfinite(wear_noise_rsd))
    return fail("wear_noise_rsd = " + std::to_string(wear_noise_rsd) + " must be > 0");
  if (!(side_force_noise_n > 0.0) || !std::isfinite(side_force_noise_n))
    return fail("side_force_noise_n = " + std::to_string(side_force_noise_n) + " must be > 0");
  if (!(alpha_select > 0.0 && alpha_select < 1.0))
    return fail("alpha_select = " + std::to_string(alpha_select) + " must be in (0, 1)");
  if (!(min_aicc_drop >= 0.0)) return fail("min_aicc_drop = " + std::to_string(min_aicc_drop) + " must be >= 0");
  if (draws < 100) return fail("draws = " + std::to_string(draws) + " must be >= 100");
  return solver.validate(error);
}

double fTestPower(double lambda, double df1, double df2, double level) {
  if (!(lambda >= 0.0) || !(df1 > 0.0) || !(df2 > 0.0) || !(level > 0.0 && level < 1.0))
    throw std::invalid_argument("fTestPower: needs lambda >= 0, df1, df2 > 0 and level in (0, 1)");
  if (lambda > kCertainLambda) return 1.0;
  if (lambda == 0.0) return level;
  return boost::math::cdf(
      boost::math::complement(boost::math::non_central_f(df1, df2, lambda), fCritical(df1, df2, level)));
}

namespace {

/// Iterations of a detection limit's search (each a full nonlinear fit): the secant steps on sqrt(lambda), which is
/// linear in the effect where the model is, need 2-6 on the rig programs; the bound is for the safeguard's
/// bisections.
constexpr int kLimitIterations = 40;
/// A limit is found when sqrt(lambda) is within this of its target, i.e. the effect within about this of the limit
/// where the model is linear in it [-].
constexpr double kLimitTolerance = 1e-3;
/// ... or when the bracket is this narrow (ratio of its ends) [-].
constexpr double kLimitBracket = 1.001;
/// Smallest effect searched, relative to the distance from the neutral value to the bound [-].
constexpr double kSmallestRelativeEffect = 1e-6;

/// The noncentrality at which an F test with (df1, df2) at `level` has the given power (bisection on the power,
/// which grows with lambda).
double lambdaForPower(double power, double df1, double df2, double level) {
  double lo = 0.0, hi = kCertainLambda;
  for (int i = 0; i < 200 && hi - lo > 1e-9 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fTestPower(mid, df1, df2, level) >= power ? hi : lo) = mid;
  }
  return hi;
}

/// The first-step F test of one term against a truth of the base model plus that term at given parameter values:
/// its noncentrality, and the noncentrality at which it reaches a wanted power.
class TermTest {
 public:
  TermTest(const TireParams& base, const DiagnosisData& data, double w3_scale, double mu_scale, Term term,
           const DetectabilityOptions& options, int terms_tried)
      : base_(base), data_(data), w3_scale_(w3_scale), mu_scale_(mu_scale), term_(term), options_(options) {
    df1_ = parameterCount({term}) - parameterCount({});
    df2_ = measuredValues(data) - parameterCount({term});
    level_ = firstStepLevel(term, options.alpha_select, terms_tried);
  }

  /// lambda with the term's parameters at `term_values` and the base orientation (or, for the orientation switch,
  /// the other one). NaN when the model cannot be evaluated there.
  double lambda(const std::vector<double>& term_values) const {
    ExtendedModelOptions model = options_.model;
    std::vector<Term> terms{term_};
    if (term_ == Term::kTurnSlipOrientation) {
      terms.clear();
      model.orientation = model.orientation == TurnSlipOrientation::kLiteral ? TurnSlipOrientation::kFlipped
                                                                             : TurnSlipOrientation::kLiteral;
    }
    const ExtendedModel truth_model(base_, model, terms, data_);
    std::vector<double> values{w3_scale_, mu_scale_};
    values.insert(values.end(), term_values.begin(), term_values.end());
    Prediction pred;
    if (!truth_model.predict(values, &pred)) return std::numeric_limits<double>::quiet_NaN();
    DiagnosisData truth = data_;
    for (std::size_t i = 0; i < truth.runs.size(); ++i)
      for (int o = 0; o < kNumOutputs; ++o)
        if (std::isfinite(truth.runs[i].measured[o])) truth.runs[i].measured[o] = pred.value(static_cast<Output>(o), i);
    return Linearisation(base_, truth, options_).baseLambda();
  }

  double power(double lambda) const { return fTestPower(lambda, df1_, df2_, level_); }
  double lambdaFor(double power) const { return lambdaForPower(power, df1_, df2_, level_); }

 private:
  const TireParams& base_;
  const DiagnosisData& data_;
  double w3_scale_, mu_scale_;
  Term term_;
  const DetectabilityOptions& options_;
  double df1_ = 1.0, df2_ = 1.0, level_ = 0.01;
};

/// Detection limits of one applicable term (detectionLimits); fills `limit` (its `term` set).
void searchLimit(const TireParams& base, const DiagnosisData& data, double w3_scale, double mu_scale, double power,
                 const DetectabilityOptions& options, int terms_tried, Term term, DetectionLimit* limit_out) {
  DetectionLimit& limit = *limit_out;
  const TermTest test(base, data, w3_scale, mu_scale, term, options, terms_tried);
  const TermInfo& info = termInfo(term);
  if (info.primary < 0) {
    limit.switch_power = test.power(test.lambda({}));
    return;
  }
  // The term's parameters at their start values, with thermal_wear's T0 at the coldest run.
  std::vector<double> values;
  for (const TermParameterSpec& p : info.parameters) values.push_back(p.initial);
  const TermParameterSpec& size = info.parameters[info.primary];
  limit.parameter = size.name;
  limit.neutral = primaryNeutral(term, base);
  if (term == Term::kThermalWear) {
    double coldest = std::numeric_limits<double>::infinity();
    for (const DiagnosisRun& r : data.runs) coldest = std::min(coldest, r.tread_temperature_c);
    values[0] = coldest;
  }
  // The power grows with lambda, so the limit is where sqrt(lambda) reaches its value at the wanted power.
  const double target = std::sqrt(test.lambdaFor(power));
  // An effect of size d > 0 on side s: the parameter neutral + s d (sigma_T = 1 / d: the effect grows as
  // sigma_T falls).
  const bool reciprocal = std::isnan(limit.neutral);
  std::vector<std::string> notes;
  for (const int side : {-1, 1}) {
    if (reciprocal && side > 0) continue;
    const double bound = side < 0 ? size.lower : size.upper;
    double d_max = reciprocal ? 1.0 / size.lower : side * (bound - limit.neutral);
    if (!(d_max > 0.0)) continue;  // the neutral value is this bound: the effect goes one way only
    const double d_min = reciprocal ? 1.0 / size.upper : kSmallestRelativeEffect * d_max;
    // sqrt(lambda) - target at effect d (NaN where the model does not evaluate).
    auto excess = [&](double d) {
      values[info.primary] = reciprocal ? 1.0 / d : limit.neutral + side * d;
      return std::sqrt(test.lambda(values)) - target;
    };
    // The model may not evaluate out to the bound (e.g. a large load std reaches zero load): shrink to where it does.
    double f_hi = excess(d_max);
    for (int i = 0; i < 20 && std::isnan(f_hi) && d_max > 2.0 * d_min; ++i) f_hi = excess(d_max *= 0.5);
    if (!(f_hi >= 0.0)) {
      char text[160];
      std::snprintf(text, sizeof(text), "%s: power %.2f at most, at %s = %.4g", side < 0 ? "below" : "above",
                    std::isnan(f_hi) ? 0.0 : test.power(std::pow(f_hi + target, 2)), size.name.c_str(),
                    values[info.primary]);
      notes.push_back(text);
      continue;
    }
    // Regula falsi (Illinois) on sqrt(lambda), which is linear in d where the model is, from the bracket
    // [0, d_max] (d = 0: no effect, lambda = 0), until an effect is within the tolerance of the target (it is then
    // the limit) or the bracket is that narrow (the upper end is). A step that leaves the bracket is replaced by a
    // bisection (in ln d once the lower end is > 0). A NaN counts as below the limit: it can only make it larger.
    double lo = 0.0, f_lo = -target, hi = d_max;
    int replaced = 0;  // which end the last step replaced: -1 lo, +1 hi
    for (int i = 0; i < kLimitIterations && hi > kLimitBracket * lo && hi > d_min; ++i) {
      double d = lo - f_lo * (hi - lo) / (f_hi - f_lo);
      if (!(d > lo && d < hi)) d = lo > 0.0 ? std::sqrt(lo * hi) : 0.5 * hi;
      d = std::max(d, d_min);
      const double f = excess(d);
      if (std::abs(f) <= kLimitTolerance * target) {
        hi = d;
        break;
      }
      if (f > 0.0) {
        hi = d, f_hi = f;
        if (replaced == 1) f_lo *= 0.5;  // Illinois: an end kept twice has its value halved
        replaced = 1;
      } else {
        lo = d;
        if (!std::isnan(f)) f_lo = f;
        if (replaced == -1) f_hi *= 0.5;
        replaced = -1;
      }
    }
    (side < 0 ? limit.below : limit.above) = reciprocal ? 1.0 / hi : limit.neutral + side * hi;
  }
  for (std::size_t i = 0; i < notes.size(); ++i) limit.note += (i ? "; " : "") + notes[i];
}

}  // namespace

std::vector<DetectionLimit> detectionLimits(const TireParams& base, const DiagnosisData& data, double w3_scale,
                                            double mu_scale, double power, const DetectabilityOptions& options) {
  std::string error;
  if (!options.validate(&error)) throw std::invalid_argument(error);
  if (!(power > 0.0 && power < 1.0))
    throw std::invalid_argument("detection limits: power = " + std::to_string(power) + " must be in (0, 1)");
  if (!(w3_scale > 0.0) || !(mu_scale > 0.0) || !std::isfinite(w3_scale) || !std::isfinite(mu_scale))
    throw std::invalid_argument("detection limits: the levels w3_scale = " + std::to_string(w3_scale) +
                                " and mu_scale = " + std::to_string(mu_scale) + " must be finite and > 0");
  std::vector<Term> applicable;
  std::vector<DetectionLimit> limits;
  for (const TermInfo& info : termLibrary()) {
    if (!candidateWanted(options, info.term)) continue;
    DetectionLimit limit;
    limit.term = info.name;
    if (termApplicable(info.term, data, &limit.note))
      applicable.push_back(info.term);
    else
      limit.note = "not applicable: " + limit.note;
    limits.push_back(limit);
  }
  const int n = measuredValues(data);
  for (DetectionLimit& limit : limits) {
    Term term;
    parseTerm(limit.term, &term);
    if (std::find(applicable.begin(), applicable.end(), term) == applicable.end()) continue;
    const int k = parameterCount({term});
    if (n - k <= 0) {
      limit.note = "too few measured values (" + std::to_string(n) + ") for its " + std::to_string(k) + " parameters";
      continue;
    }
    try {
      searchLimit(base, data, w3_scale, mu_scale, power, options, static_cast<int>(applicable.size()), term, &limit);
    } catch (const std::exception& e) {
      limit.note = std::string("not computed: ") + e.what();  // e.g. the base model does not fit the truth
    }
  }
  return limits;
}

}  // namespace diagnosis
}  // namespace tread_wear
