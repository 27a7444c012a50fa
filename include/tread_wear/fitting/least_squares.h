#pragma once
/// @file least_squares.h
/// General bounded nonlinear least squares over named parameters, with Gaussian priors, a Ceres-style
/// summary (standard errors, correlations, condition number, bounds hit) and leave-one-group-out
/// cross-validation. The tread wear calibration (calibration.h) and the mismatch diagnosis use it; nothing
/// in here knows about tires.
///
/// Problem: parameters theta (by name, with bounds), records r = 0..N-1 (test runs, conditions, ...),
/// a residual function that returns residuals_per_record residuals for each requested record, and
/// optionally a group label per record (leave-one-group-out cross-validation; records of one group, e.g.
/// repeats of one test condition, are held out together). The solver minimises
///     cost = 1/2 sum_records |r_i(theta)|^2 + 1/2 sum_priors ((u_j - u_j,prior) / sigma_j)^2
/// subject to lower_j <= theta_j <= upper_j, where u is the internal coordinate of a parameter:
///     log_scale:  u = ln(theta)             (sigma_j is then a relative standard deviation)
///     linear:     u = theta / scale_j       (sigma_j in units of scale_j)
/// with scale_j = |initial|, or half the bound range when initial = 0, or 1 when that range is infinite.
///
/// Solver: Ceres Solver 2.1 (Debian libceres-dev), Levenberg-Marquardt trust region with dense QR; bounds are
/// native (projected steps), which Eigen's unsupported LevenbergMarquardt lacks. The Jacobian is taken by
/// finite differences in u (central by default, one-sided next to a bound) because the residual function is
/// a black box (a brush model solved numerically).
///
/// Statistics at the solution (as in nonlinear regression, e.g. Bates & Watts):
///   J = d(residuals, prior rows)/du over the parameters NOT at a bound; s^2 = sum(data r^2) / (N_data - p_free);
///   Cov(u) = s^2 (J^T J)^-1; std_error(theta) = |dtheta/du| sqrt(Cov_jj); correlation = Cov_jk / sqrt(Cov_jj Cov_kk).
///   With robust_covariance the covariance is the heteroscedasticity-consistent sandwich HC3 instead (MacKinnon
///   and White 1985; Long and Ervin 2000 recommend it for small samples): Cov(u) = B M B with B = (J^T J)^-1 and
///   M = sum over data rows of j_i j_i^T r_i^2 / (1 - h_i)^2, h_i = j_i^T B j_i the leverage (prior rows add
///   j_k j_k^T, their variance being known). It stays honest when the residual variance differs between records,
///   e.g. error ratios of a transducer with additive noise, where s^2 (J^T J)^-1 understates the uncertainty of a
///   parameter that the noisier records determine.
///   condition_number = sigma_max / sigma_min of J with unit-norm columns (1 = orthogonal directions; large =
///   poorly identified combinations). Parameters at a bound are reported with at_bound set and a NaN
///   standard error: the quadratic approximation does not hold there. With N_data <= p_free the standard
///   errors are NaN (no residual variance).
/// Limits: local optimum from the given start; standard errors are linearised (Jacobian) estimates.

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace tread_wear {

/// One free parameter, by name, in its physical unit.
struct FitParameter {
  std::string name;
  double initial = 0.0;                                        ///< start value [unit of the parameter]
  double lower = -std::numeric_limits<double>::infinity();     ///< lower bound [unit]
  double upper = std::numeric_limits<double>::infinity();      ///< upper bound [unit]
  bool log_scale = false;                                      ///< optimise ln(value); needs lower > 0
  double prior_value = std::numeric_limits<double>::quiet_NaN();  ///< prior centre [unit]; NaN = no prior
  double prior_sigma = std::numeric_limits<double>::quiet_NaN();  ///< prior std in internal coordinates, > 0
};

/// Writes residuals_per_record residuals for each of `records` (in that order) into `residuals`
/// (size records.size() * residuals_per_record), given the parameter values (physical, in the order of
/// LeastSquaresProblem::parameters). Returns false when the model cannot be evaluated there.
using ResidualFunction =
    std::function<bool(const std::vector<double>& values, const std::vector<int>& records, double* residuals)>;

struct LeastSquaresProblem {
  std::vector<FitParameter> parameters;
  int num_records = 0;
  int residuals_per_record = 1;
  std::vector<std::string> groups;  ///< cross-validation group per record; empty = each record its own group
  ResidualFunction residuals;

  /// Names the first inconsistent field (sizes, bounds, start outside bounds, log scale with lower <= 0, ...).
  bool validate(std::string* error) const;
};

struct LeastSquaresOptions {
  int max_iterations = 100;            ///< trust-region iterations, >= 1
  double function_tolerance = 1e-10;   ///< Ceres: relative cost change for convergence
  double gradient_tolerance = 1e-12;   ///< Ceres: max-norm of the projected gradient
  double parameter_tolerance = 1e-10;  ///< Ceres: relative step size
  double jacobian_step = 1e-6;         ///< finite-difference step in internal coordinates u, > 0
  bool central_differences = true;     ///< central (2p evaluations) or forward (p) differences
  double bound_tolerance = 1e-6;       ///< |u - u_bound| <= tol (1 + |u_bound|) counts as at the bound
  bool robust_covariance = false;      ///< HC3 sandwich standard errors and correlations (see above)
  /// Bounded problems: Ceres shortens each projected trust-region step by an Armijo line search whose cubic
  /// interpolation takes the gradient, i.e. a whole finite-difference Jacobian (2p residual evaluations), at every
  /// trial step. false: no line search; a projected step that does not lower the cost is rejected and the trust
  /// region shrinks, one residual evaluation per trial. Where a residual evaluation is expensive (the diagnosis's
  /// brush model on drive cells) false costs a fraction.
  bool bounded_line_search = true;
  /// Hold the parameters that settle on a bound (kept there for 3 successful iterations) and solve for the others
  /// alone, then release them if a step inwards lowers the cost. Ceres's projected steps otherwise crawl along an
  /// active bound and may stop short of the constrained optimum on the parameter tolerance (test
  /// WithoutTheBoundedLineSearchTheConstrainedOptimumIsReachedWithFewerEvaluations).
  bool hold_bound_parameters = false;

  bool validate(std::string* error) const;
};

enum class TerminationType {
  kConvergence,    ///< a tolerance was met
  kNoConvergence,  ///< iteration limit reached; the solution may still be usable
  kFailure         ///< the residual function failed or the problem was invalid
};
const char* terminationName(TerminationType type);

struct ParameterEstimate {
  std::string name;
  double value = 0.0;      ///< [unit]
  double std_error = 0.0;  ///< [unit]; NaN at a bound or without residual variance; inf if unidentifiable
  double lower = 0.0, upper = 0.0;
  bool at_lower = false, at_upper = false;
  bool atBound() const { return at_lower || at_upper; }
};

/// Outcome of one fit, in the spirit of Ceres' Solver::Summary.
struct LeastSquaresSummary {
  double initial_cost = 0.0;  ///< 1/2 sum r^2 at the start (data and prior rows)
  double final_cost = 0.0;    ///< 1/2 sum r^2 at the solution
  int iterations = 0;
  TerminationType termination = TerminationType::kFailure;
  std::string message;       ///< solver message
  bool usable = false;       ///< solution may be used (Ceres' IsSolutionUsable)
  std::vector<ParameterEstimate> parameters;
  Eigen::MatrixXd correlation;  ///< p x p over all parameters; rows/cols of bound parameters are NaN (diag 1)
  double condition_number = std::numeric_limits<double>::quiet_NaN();  ///< of the column-scaled Jacobian
  double residual_variance = std::numeric_limits<double>::quiet_NaN(); ///< s^2 of the data residuals
  int degrees_of_freedom = 0;                                          ///< N_data - p_free
  /// std_error and correlation are the HC3 sandwich (LeastSquaresOptions::robust_covariance, with J^T J
  /// regular); else the classic s^2 (J^T J)^-1.
  bool robust_covariance = false;
  std::vector<int> records;        ///< records fitted
  std::vector<double> residuals;   ///< data residuals at the solution, records.size() * residuals_per_record

  std::vector<double> values() const;
  /// Multi-line human-readable report (cost, termination, parameters with std errors, correlations).
  std::string report() const;
};

/// Fits `records` (all when empty). Never throws for a bad problem: returns termination kFailure and the
/// validation message.
LeastSquaresSummary solveLeastSquares(const LeastSquaresProblem& problem, const LeastSquaresOptions& options,
                                      const std::vector<int>& records = {});

/// Unique group labels in order of first appearance (each record its own group "<index>" when
/// problem.groups is empty), and the records of each.
std::vector<std::pair<std::string, std::vector<int>>> crossValidationFolds(const LeastSquaresProblem& problem);

struct CrossValidationFold {
  std::string group;
  std::vector<int> held_out;            ///< records of this group
  std::vector<double> values;           ///< parameters fitted without the group
  TerminationType termination = TerminationType::kFailure;
  bool usable = false;
  std::vector<double> held_out_residuals;  ///< residuals of the held-out records at `values`
};

struct CrossValidationResult {
  std::vector<CrossValidationFold> folds;
  /// Held-out residual of every record (record-major, residuals_per_record each), NaN if its fold failed.
  std::vector<double> held_out_residuals;
};

/// Leave-one-group-out: for each group, fit all other records from the problem's initial values and
/// evaluate the held-out records. Groups that would leave no training record are skipped (NaN residuals).
CrossValidationResult crossValidate(const LeastSquaresProblem& problem, const LeastSquaresOptions& options);

}  // namespace tread_wear
