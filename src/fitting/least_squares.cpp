#include "tread_wear/fitting/least_squares.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>

#include <ceres/ceres.h>

#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

bool hasPrior(const FitParameter& p) { return std::isfinite(p.prior_value) && std::isfinite(p.prior_sigma); }

/// Typical magnitude of a linear parameter: |initial|, else half its finite range, else 1.
double linearScale(const FitParameter& p) {
  if (p.initial != 0.0) return std::abs(p.initial);
  if (std::isfinite(p.upper - p.lower)) return 0.5 * (p.upper - p.lower);
  return 1.0;
}

/// Maps between physical values and the internal coordinates u the solver works in.
class Coordinates {
 public:
  explicit Coordinates(const std::vector<FitParameter>& params) : params_(params) {
    for (const FitParameter& p : params)
      scale_.push_back(p.log_scale ? 1.0 : linearScale(p));
  }
  double toInternal(int j, double value) const {
    if (params_[j].log_scale) return value > 0.0 ? std::log(value) : (value == 0.0 ? -kInf : kNaN);
    return value / scale_[j];
  }
  double toValue(int j, double u) const { return params_[j].log_scale ? std::exp(u) : u * scale_[j]; }
  /// |d value / du| at u.
  double derivative(int j, double u) const { return params_[j].log_scale ? std::exp(u) : scale_[j]; }
  double lowerInternal(int j) const { return toInternal(j, params_[j].lower); }
  double upperInternal(int j) const { return toInternal(j, params_[j].upper); }
  std::vector<double> values(const double* u) const {
    std::vector<double> v(params_.size());
    for (size_t j = 0; j < v.size(); ++j) v[j] = toValue(static_cast<int>(j), u[j]);
    return v;
  }

 private:
  const std::vector<FitParameter>& params_;
  std::vector<double> scale_;
};

/// Data residuals of the selected records followed by one row per prior, with a finite-difference
/// Jacobian in the internal coordinates.
class FittingCost final : public ceres::CostFunction {
 public:
  FittingCost(const LeastSquaresProblem& problem, const LeastSquaresOptions& options, const std::vector<int>& records)
      : problem_(problem), options_(options), records_(records), coords_(problem.parameters) {
    n_data_ = static_cast<int>(records.size()) * problem.residuals_per_record;
    for (size_t j = 0; j < problem.parameters.size(); ++j)
      if (hasPrior(problem.parameters[j])) prior_index_.push_back(static_cast<int>(j));
    set_num_residuals(n_data_ + static_cast<int>(prior_index_.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(problem.parameters.size()));
  }

  int numData() const { return n_data_; }

  bool residualsAt(const double* u, double* r) const {
    const std::vector<double> values = coords_.values(u);
    if (!problem_.residuals(values, records_, r)) return false;
    for (int i = 0; i < n_data_; ++i)
      if (!std::isfinite(r[i])) return false;
    for (size_t k = 0; k < prior_index_.size(); ++k) {
      const int j = prior_index_[k];
      const FitParameter& p = problem_.parameters[j];
      r[n_data_ + k] = (u[j] - coords_.toInternal(j, p.prior_value)) / p.prior_sigma;
    }
    return true;
  }

  /// Row-major Jacobian (num_residuals x p) by finite differences; one-sided next to a bound.
  bool jacobianAt(const double* u, const double* r0, double* jac) const {
    const int n = static_cast<int>(problem_.parameters.size());
    const int m = num_residuals();
    std::vector<double> up(u, u + n), rp(m), rm(m);
    const double h = options_.jacobian_step;
    for (int j = 0; j < n; ++j) {
      const double lo = coords_.lowerInternal(j), hi = coords_.upperInternal(j);
      const bool room_up = !(u[j] + h > hi), room_down = !(u[j] - h < lo);
      double step_up = h, step_down = h;
      if (options_.central_differences && room_up && room_down) {
        up[j] = u[j] + h;
        if (!residualsAt(up.data(), rp.data())) return false;
        up[j] = u[j] - h;
        if (!residualsAt(up.data(), rm.data())) return false;
      } else if (room_up) {
        up[j] = u[j] + h;
        if (!residualsAt(up.data(), rp.data())) return false;
        std::copy(r0, r0 + m, rm.begin());
        step_down = 0.0;
      } else {
        up[j] = u[j] - h;
        if (!residualsAt(up.data(), rm.data())) return false;
        std::copy(r0, r0 + m, rp.begin());
        step_up = 0.0;
      }
      up[j] = u[j];
      for (int i = 0; i < m; ++i) jac[i * n + j] = (rp[i] - rm[i]) / (step_up + step_down);
    }
    return true;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    if (!residualsAt(parameters[0], residuals)) return false;
    if (jacobians != nullptr && jacobians[0] != nullptr) return jacobianAt(parameters[0], residuals, jacobians[0]);
    return true;
  }

 private:
  const LeastSquaresProblem& problem_;
  const LeastSquaresOptions& options_;
  const std::vector<int>& records_;
  Coordinates coords_;
  int n_data_ = 0;
  std::vector<int> prior_index_;
};

TerminationType mapTermination(ceres::TerminationType t) {
  switch (t) {
    case ceres::CONVERGENCE:
    case ceres::USER_SUCCESS: return TerminationType::kConvergence;
    case ceres::NO_CONVERGENCE: return TerminationType::kNoConvergence;
    default: return TerminationType::kFailure;
  }
}

/// Standard errors, correlations and the condition number from the Jacobian at the solution.
void fillStatistics(const LeastSquaresProblem& problem, const FittingCost& cost, const Coordinates& coords,
                    const std::vector<double>& u, const std::vector<double>& r, bool robust,
                    LeastSquaresSummary* s) {
  const int n = static_cast<int>(problem.parameters.size());
  const int m = cost.num_residuals();
  s->correlation = Eigen::MatrixXd::Constant(n, n, kNaN);
  for (int j = 0; j < n; ++j) s->correlation(j, j) = 1.0;

  std::vector<int> free_index;
  for (int j = 0; j < n; ++j)
    if (!s->parameters[j].atBound()) free_index.push_back(j);
  const int p = static_cast<int>(free_index.size());
  s->degrees_of_freedom = cost.numData() - p;
  double ssr = 0.0;
  for (int i = 0; i < cost.numData(); ++i) ssr += r[i] * r[i];
  s->residual_variance = s->degrees_of_freedom > 0 ? ssr / s->degrees_of_freedom : kNaN;
  if (p == 0) return;

  std::vector<double> jac(static_cast<size_t>(m) * n);
  if (!cost.jacobianAt(u.data(), r.data(), jac.data())) return;
  Eigen::MatrixXd jf(m, p);
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < p; ++k) jf(i, k) = jac[static_cast<size_t>(i) * n + free_index[k]];

  Eigen::VectorXd norms = jf.colwise().norm();
  Eigen::MatrixXd scaled = jf;
  for (int k = 0; k < p; ++k) scaled.col(k) /= norms(k) > 0.0 ? norms(k) : 1.0;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd_scaled(scaled);
  const Eigen::VectorXd sv = svd_scaled.singularValues();
  s->condition_number = sv(sv.size() - 1) > 0.0 ? sv(0) / sv(sv.size() - 1) : kInf;

  // (J^T J)^-1 through the SVD of the column-scaled J: robust when J is ill-conditioned.
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
  const Eigen::VectorXd w = svd.singularValues();
  const double cutoff = w(0) * 1e-12;
  bool singular = false;
  Eigen::VectorXd winv2(w.size());
  for (int k = 0; k < w.size(); ++k) {
    singular = singular || !(w(k) > cutoff);
    winv2(k) = w(k) > cutoff ? 1.0 / (w(k) * w(k)) : 0.0;
  }
  const Eigen::MatrixXd& v = svd.matrixV();
  Eigen::MatrixXd cov_scaled = v * winv2.asDiagonal() * v.transpose();
  // Scale of cov_scaled: s^2 for the classic estimate; 1 for the sandwich, whose meat carries the residuals.
  double variance_factor = s->residual_variance;
  if (robust && !singular) {
    Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(p, p);
    for (int i = 0; i < m; ++i) {
      const Eigen::VectorXd row = scaled.row(i).transpose();
      double omega = 1.0;  // prior rows: unit variance by construction
      if (i < cost.numData()) {
        const double leverage = row.dot(cov_scaled * row);
        const double one_minus_h = std::max(1.0 - leverage, 1e-6);
        omega = r[i] * r[i] / (one_minus_h * one_minus_h);
      }
      meat.noalias() += omega * row * row.transpose();
    }
    cov_scaled = cov_scaled * meat * cov_scaled;
    variance_factor = std::isfinite(s->residual_variance) ? 1.0 : kNaN;
    s->robust_covariance = true;
  }
  for (int a = 0; a < p; ++a)
    for (int b = 0; b < p; ++b) {
      const double denom = std::sqrt(cov_scaled(a, a) * cov_scaled(b, b));
      s->correlation(free_index[a], free_index[b]) = denom > 0.0 ? cov_scaled(a, b) / denom : kNaN;
    }
  for (int a = 0; a < p; ++a) {
    const int j = free_index[a];
    const double var_u = cov_scaled(a, a) / (norms(a) * norms(a));
    s->parameters[j].std_error = singular        ? kInf
                                 : !std::isfinite(variance_factor) ? kNaN
                                 : coords.derivative(j, u[j]) * std::sqrt(variance_factor * var_u);
  }
}

}  // namespace

const char* terminationName(TerminationType type) {
  switch (type) {
    case TerminationType::kConvergence: return "convergence";
    case TerminationType::kNoConvergence: return "no_convergence";
    case TerminationType::kFailure: return "failure";
  }
  return "unknown";
}

bool LeastSquaresProblem::validate(std::string* error) const {
  auto fail = [&](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (parameters.empty()) return fail("parameters: empty; at least one parameter must be free");
  if (num_records < 1) return failValidation(error, "num_records", num_records, ">= 1");
  if (residuals_per_record < 1)
    return failValidation(error, "residuals_per_record", residuals_per_record, ">= 1");
  if (!groups.empty() && static_cast<int>(groups.size()) != num_records)
    return fail("groups: size " + std::to_string(groups.size()) + " != num_records " + std::to_string(num_records));
  if (!residuals) return fail("residuals: no residual function");
  for (size_t j = 0; j < parameters.size(); ++j) {
    const FitParameter& p = parameters[j];
    const std::string who = "parameter '" + p.name + "'";
    if (p.name.empty()) return fail("parameter " + std::to_string(j) + ": empty name");
    for (size_t k = 0; k < j; ++k)
      if (parameters[k].name == p.name) return fail(who + ": listed twice");
    if (!std::isfinite(p.initial)) return fail(who + ": initial value is not finite");
    if (std::isnan(p.lower) || std::isnan(p.upper) || !(p.lower < p.upper))
      return fail(who + ": bounds [" + std::to_string(p.lower) + ", " + std::to_string(p.upper) +
                  "] must satisfy lower < upper");
    if (p.initial < p.lower || p.initial > p.upper)
      return fail(who + ": initial " + std::to_string(p.initial) + " outside its bounds [" +
                  std::to_string(p.lower) + ", " + std::to_string(p.upper) + "]");
    if (p.log_scale && !(p.lower > 0.0))
      return fail(who + ": log scale needs lower bound > 0, got " + std::to_string(p.lower));
    if (std::isfinite(p.prior_value) != std::isfinite(p.prior_sigma))
      return fail(who + ": prior needs both prior_value and prior_sigma");
    if (hasPrior(p) && !(p.prior_sigma > 0.0))
      return fail(who + ": prior_sigma = " + std::to_string(p.prior_sigma) + ": must be > 0");
    if (hasPrior(p) && p.log_scale && !(p.prior_value > 0.0))
      return fail(who + ": log-scale prior_value must be > 0");
  }
  return true;
}

bool LeastSquaresOptions::validate(std::string* error) const {
  auto fail = [&](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (max_iterations < 1) return failValidation(error, "max_iterations", max_iterations, ">= 1");
  if (!(function_tolerance >= 0.0) || !(gradient_tolerance >= 0.0) || !(parameter_tolerance >= 0.0))
    return fail("tolerances must be >= 0");
  if (!(jacobian_step > 0.0)) return failValidation(error, "jacobian_step", jacobian_step, "> 0");
  if (!(bound_tolerance >= 0.0)) return fail("bound_tolerance must be >= 0");
  return true;
}

std::vector<double> LeastSquaresSummary::values() const {
  std::vector<double> v;
  for (const ParameterEstimate& p : parameters) v.push_back(p.value);
  return v;
}

std::string LeastSquaresSummary::report() const {
  std::ostringstream os;
  os << std::setprecision(6);
  os << "termination: " << terminationName(termination) << " (" << message << "), usable: " << (usable ? "yes" : "no")
     << "\niterations: " << iterations << ", cost " << initial_cost << " -> " << final_cost
     << ", dof: " << degrees_of_freedom << ", condition number: " << condition_number
     << "\nstandard errors: " << (robust_covariance ? "HC3 sandwich" : "classic s^2 (J^T J)^-1") << "\n";
  for (const ParameterEstimate& p : parameters) {
    os << "  " << std::setw(14) << std::left << p.name << std::right << " = " << std::setw(13) << p.value
       << " +- " << std::setw(12) << p.std_error << "  [" << p.lower << ", " << p.upper << "]"
       << (p.at_lower ? "  AT LOWER BOUND" : "") << (p.at_upper ? "  AT UPPER BOUND" : "") << "\n";
  }
  if (parameters.size() > 1) {
    os << "correlations:\n";
    for (int a = 0; a < correlation.rows(); ++a) {
      os << "  ";
      for (int b = 0; b < correlation.cols(); ++b) os << std::setw(8) << std::fixed << std::setprecision(3)
                                                      << correlation(a, b);
      os << "\n";
    }
  }
  return os.str();
}

/// Successful iterations with the same parameters on their bounds after which the first solve of
/// LeastSquaresOptions::hold_bound_parameters ends (the bound set has then settled).
constexpr int kSettledBoundIterations = 3;

/// Ceres runs over the internal coordinates, with the bounds, optionally holding some parameters where they are
/// (hold_bound_parameters: Ceres's projected steps crawl along an active bound, the free parameters' part of each
/// step being solved jointly with the clipped one).
class BoundedSolve {
 public:
  BoundedSolve(FittingCost* cost, const Coordinates& coords, const LeastSquaresOptions& options)
      : cost_(cost), coords_(coords), options_(options) {}

  /// Parameters at one of their bounds (bound_tolerance).
  std::vector<int> atBounds(const std::vector<double>& u) const {
    std::vector<int> at;
    for (int j = 0; j < static_cast<int>(u.size()); ++j)
      if (onBound(u[j], coords_.lowerInternal(j)) || onBound(u[j], coords_.upperInternal(j))) at.push_back(j);
    return at;
  }

  /// Solves from *u, the parameters `held` fixed; with `stop_when_settled`, ends once the same non-empty set of
  /// parameters has sat on its bounds for kSettledBoundIterations successful iterations.
  ceres::Solver::Summary run(std::vector<double>* u, const std::vector<int>& held, bool stop_when_settled) const {
    ceres::Problem::Options problem_options;
    problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    problem.AddResidualBlock(cost_, nullptr, u->data());
    if (!held.empty()) problem.SetManifold(u->data(), new ceres::SubsetManifold(static_cast<int>(u->size()), held));
    for (int j = 0; j < static_cast<int>(u->size()); ++j) {
      const double lo = coords_.lowerInternal(j), hi = coords_.upperInternal(j);
      if (std::isfinite(lo)) problem.SetParameterLowerBound(u->data(), j, lo);
      if (std::isfinite(hi)) problem.SetParameterUpperBound(u->data(), j, hi);
    }
    ceres::Solver::Options so;
    so.minimizer_type = ceres::TRUST_REGION;
    so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = options_.max_iterations;
    so.function_tolerance = options_.function_tolerance;
    so.gradient_tolerance = options_.gradient_tolerance;
    so.parameter_tolerance = options_.parameter_tolerance;
    if (!options_.bounded_line_search) so.max_num_line_search_step_size_iterations = 0;  // Ceres: no line search
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    so.num_threads = 1;
    SettledBounds settled(*this, *u);
    if (stop_when_settled) {
      so.update_state_every_iteration = true;
      so.callbacks.push_back(&settled);
    }
    ceres::Solver::Summary cs;
    ceres::Solve(so, &problem, &cs);
    return cs;
  }

  /// The held parameters whose move off their bound, by the Jacobian step inwards, lowers the cost.
  std::vector<int> leavingBounds(const std::vector<double>& u, const std::vector<int>& held) const {
    const int m = cost_->num_residuals();
    std::vector<double> r(m), moved = u;
    std::vector<int> leaving;
    if (!cost_->residualsAt(u.data(), r.data())) return leaving;
    const double at = squaredNorm(r);
    for (int j : held) {
      const bool on_lower = onBound(u[j], coords_.lowerInternal(j));
      moved[j] = u[j] + (on_lower ? 1.0 : -1.0) * options_.jacobian_step;
      if (cost_->residualsAt(moved.data(), r.data()) && squaredNorm(r) < at) leaving.push_back(j);
      moved[j] = u[j];
    }
    return leaving;
  }

 private:
  /// True if the internal value u lies on the (finite) bound, within bound_tolerance.
  bool onBound(double u, double bound) const {
    return std::isfinite(bound) && std::abs(u - bound) <= options_.bound_tolerance * (1.0 + std::abs(bound));
  }
  static double squaredNorm(const std::vector<double>& r) {
    double sum = 0.0;
    for (double v : r) sum += v * v;
    return sum;
  }

  /// The callback of run's stop_when_settled.
  class SettledBounds final : public ceres::IterationCallback {
   public:
    SettledBounds(const BoundedSolve& solve, const std::vector<double>& u) : solve_(solve), u_(u) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
      if (!summary.step_is_successful) return ceres::SOLVER_CONTINUE;
      const std::vector<int> now = solve_.atBounds(u_);
      streak_ = !now.empty() && now == last_ ? streak_ + 1 : 0;
      last_ = now;
      return streak_ >= kSettledBoundIterations ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
    }

   private:
    const BoundedSolve& solve_;
    const std::vector<double>& u_;
    std::vector<int> last_;
    int streak_ = 0;
  };

  FittingCost* cost_;
  const Coordinates& coords_;
  const LeastSquaresOptions& options_;
};

LeastSquaresSummary solveLeastSquares(const LeastSquaresProblem& problem, const LeastSquaresOptions& options,
                                      const std::vector<int>& records_in) {
  LeastSquaresSummary s;
  std::string error;
  if (!problem.validate(&error) || !options.validate(&error)) {
    s.message = error;
    return s;
  }
  std::vector<int> records = records_in;
  if (records.empty())
    for (int i = 0; i < problem.num_records; ++i) records.push_back(i);
  for (int r : records)
    if (r < 0 || r >= problem.num_records) {
      s.message = "record index " + std::to_string(r) + " out of range";
      return s;
    }
  s.records = records;

  const int n = static_cast<int>(problem.parameters.size());
  Coordinates coords(problem.parameters);
  std::vector<double> u(n);
  for (int j = 0; j < n; ++j) u[j] = coords.toInternal(j, problem.parameters[j].initial);

  FittingCost cost(problem, options, records);
  const BoundedSolve solve(&cost, coords, options);
  ceres::Solver::Summary cs = solve.run(&u, {}, options.hold_bound_parameters);
  s.initial_cost = cs.initial_cost;
  s.iterations = static_cast<int>(cs.iterations.size()) - 1;
  // The parameters that settled on a bound held, the others solved alone; those that would leave their bound are
  // released and the rest solved again, until none would (each round releases one at least). A failed solve keeps
  // the last solution.
  std::vector<int> held = solve.atBounds(u);
  while (options.hold_bound_parameters && cs.IsSolutionUsable() && !held.empty()) {
    if (static_cast<int>(held.size()) < n) {
      std::vector<double> v = u;
      const ceres::Solver::Summary next = solve.run(&v, held, false);
      s.iterations += static_cast<int>(next.iterations.size()) - 1;
      if (!next.IsSolutionUsable()) break;
      u = v;
      cs = next;
    }
    const std::vector<int> leaving = solve.leavingBounds(u, held);
    if (leaving.empty()) break;
    std::vector<int> kept;
    for (int j : held)
      if (std::find(leaving.begin(), leaving.end(), j) == leaving.end()) kept.push_back(j);
    held = kept;
    if (held.empty()) {
      cs = solve.run(&u, {}, false);
      s.iterations += static_cast<int>(cs.iterations.size()) - 1;
    }
  }
  s.final_cost = cs.final_cost;
  s.termination = mapTermination(cs.termination_type);
  s.message = cs.message;
  s.usable = cs.IsSolutionUsable();

  for (int j = 0; j < n; ++j) {
    const FitParameter& p = problem.parameters[j];
    ParameterEstimate e;
    e.name = p.name;
    e.value = coords.toValue(j, u[j]);
    e.lower = p.lower;
    e.upper = p.upper;
    const double lo = coords.lowerInternal(j), hi = coords.upperInternal(j);
    e.at_lower = std::isfinite(lo) && std::abs(u[j] - lo) <= options.bound_tolerance * (1.0 + std::abs(lo));
    e.at_upper = std::isfinite(hi) && std::abs(u[j] - hi) <= options.bound_tolerance * (1.0 + std::abs(hi));
    e.std_error = kNaN;
    s.parameters.push_back(e);
  }

  std::vector<double> r(cost.num_residuals());
  if (!cost.residualsAt(u.data(), r.data())) {
    s.termination = TerminationType::kFailure;
    s.usable = false;
    s.message += "; residual function failed at the solution";
    return s;
  }
  s.residuals.assign(r.begin(), r.begin() + cost.numData());
  fillStatistics(problem, cost, coords, u, r, options.robust_covariance, &s);
  return s;
}

std::vector<std::pair<std::string, std::vector<int>>> crossValidationFolds(const LeastSquaresProblem& problem) {
  std::vector<std::pair<std::string, std::vector<int>>> folds;
  for (int i = 0; i < problem.num_records; ++i) {
    const std::string label =
        problem.groups.empty() ? std::to_string(i) : problem.groups[static_cast<size_t>(i)];
    auto it = std::find_if(folds.begin(), folds.end(), [&](const auto& f) { return f.first == label; });
    if (it == folds.end()) {
      folds.push_back({label, {i}});
    } else {
      it->second.push_back(i);
    }
  }
  return folds;
}

CrossValidationResult crossValidate(const LeastSquaresProblem& problem, const LeastSquaresOptions& options) {
  CrossValidationResult result;
  const int rpr = problem.residuals_per_record;
  result.held_out_residuals.assign(static_cast<size_t>(problem.num_records) * rpr, kNaN);
  std::string error;
  if (!problem.validate(&error)) return result;
  for (const auto& [group, held_out] : crossValidationFolds(problem)) {
    CrossValidationFold fold;
    fold.group = group;
    fold.held_out = held_out;
    std::vector<int> training;
    for (int i = 0; i < problem.num_records; ++i)
      if (std::find(held_out.begin(), held_out.end(), i) == held_out.end()) training.push_back(i);
    if (!training.empty()) {
      const LeastSquaresSummary fit = solveLeastSquares(problem, options, training);
      fold.values = fit.values();
      fold.termination = fit.termination;
      fold.usable = fit.usable;
      fold.held_out_residuals.assign(held_out.size() * rpr, kNaN);
      if (fit.usable && problem.residuals(fold.values, held_out, fold.held_out_residuals.data())) {
        for (size_t k = 0; k < held_out.size(); ++k)
          for (int c = 0; c < rpr; ++c)
            result.held_out_residuals[static_cast<size_t>(held_out[k]) * rpr + c] =
                fold.held_out_residuals[k * rpr + c];
      }
    }
    result.folds.push_back(std::move(fold));
  }
  return result;
}

}  // namespace tread_wear
