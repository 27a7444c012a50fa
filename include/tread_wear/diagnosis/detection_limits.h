#pragma once
/// @file detection_limits.h
/// Step 6 of the diagnosis (diagnosis.h): what a verdict rules out.
/// Detection limits (detectionLimits): the power of step 4's first F test on the user's own recordings, for a `none`
/// verdict to say what it rules out. For each applicable term, its size parameter is moved away from the value at
/// which the term has no effect (both ways where both are possible) until the first-step F test reaches the
/// wanted power (0.8 by convention, Cohen 1988) against the calibrated base model, at the noise levels the
/// diagnosis estimated. The truth is the base model at its fitted levels plus the term; lambda comes from a full
/// (nonlinear) base fit to it, so large limits are not linearised. Conventions: thermal_wear is searched in sigma_T
/// with T0 at the coldest run (wear then rises over the observed temperatures); load_fluctuation's limit is the
/// multiple of the recorded load std; turn_slip_orientation is a switch, so it reports the power of the switch.

/// The power: P(F'(k_A, n - p_A; lambda_A) > F_crit) at the first step's level (alpha_select / m over the m terms
/// tried; twice that for a term whose no-effect value is a bound, the boundary test), F' the noncentral F
/// distribution (Boost.Math), n the measured values, p_A the model's parameters, k_A those of the term, lambda_A the
/// smallest residual sum of squares of the base model on the truth in noise units (side force (Fy - Fy_true) /
/// sigma_F, wear (W / W_true - 1) / s_W). The linearised models below serve the detectability reference of the
/// proving grounds (proving/detectability.h).

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/fitting/least_squares.h"

namespace tread_wear {
namespace diagnosis {

struct DetectabilityOptions {
  double wear_noise_rsd = 0.05;     ///< relative wear noise s_W [-], > 0
  double side_force_noise_n = 1.0;  ///< additive side-force noise sigma_F [N], > 0
  double alpha_select = 0.01;       ///< the diagnosis's family-wise level of the term tests (0, 1)
  double min_aicc_drop = 2.0;       ///< the diagnosis's AICc drop for an eligible term, >= 0
  int draws = 10000;                ///< noise draws of the oracle verdicts, >= 100
  std::uint64_t seed = 1;           ///< of the noise draws
  std::vector<Term> candidates;     ///< terms to try; empty = every applicable term (as the diagnosis)
  ExtendedModelOptions model;       ///< preset and orientation, as in the diagnosis
  LeastSquaresOptions solver;

  bool validate(std::string* error) const;
};

/// A parameter of the hidden term's model fitted to its own noise-free recordings (the truth), with the standard
/// error of its estimate on noisy recordings (linearised, known noise): the reference for the estimate's precision.
struct ReferenceParameter {
  std::string name;
  double value = 0.0;                                           ///< [unit of the parameter]
  double std_error = std::numeric_limits<double>::quiet_NaN();  ///< [unit]; NaN on a bound
};

/// A model fitted to the noise-free recordings and linearised there (Gauss-Newton), in noise units over the
/// measured values.
struct LinearisedModel {
  std::vector<Term> terms;
  int k = 0;  ///< parameters, as the diagnosis counts them
  bool usable = false;
  Eigen::VectorXd residual;        ///< r_M: noise-free residual at the best fit
  Eigen::MatrixXd basis;           ///< orthonormal basis of the free Jacobian columns
  Eigen::MatrixXd pseudo_inverse;  ///< of the free Jacobian columns: the parameter step that fits a residual change
  int one_sided = -1;              ///< column of a parameter on its lower bound that may only grow, -1 if none
  std::vector<ReferenceParameter> parameters;  ///< best-fit values; standard errors from the free columns
  Eigen::MatrixXd basis_without;               ///< basis without that column

  /// Residual sum of squares on truth + noise (noise in noise units over the measured values).
  double rss(const Eigen::VectorXd& noise) const {
    const Eigen::VectorXd e = residual - noise;
    if (one_sided >= 0) {
      // The parameter step that fits -e is -(R^-1 Q^T e); a negative step would cross the bound.
      if (-pseudo_inverse.row(one_sided).dot(e) < 0.0)
        return e.squaredNorm() - (basis_without.transpose() * e).squaredNorm();
    }
    return e.squaredNorm() - (basis.transpose() * e).squaredNorm();
  }
};

/// Parameters of base + terms: the two levels, the terms' parameters, and the orientation switch counted as one
/// (as the diagnosis's AICc does).
int parameterCount(const std::vector<Term>& terms);
/// Whether the options ask for the term (no candidates: every term).
bool candidateWanted(const DetectabilityOptions& options, Term term);
/// Level of the first-step F test of a term among `terms_tried` (Bonferroni), doubled for a term whose no-effect
/// value is a bound (the boundary test: p / 2 < level while the estimate is off the bound).
double firstStepLevel(Term term, double alpha_select, int terms_tried);
/// Measured values of the recordings (side force and wear, where recorded).
int measuredValues(const DiagnosisData& data);
/// Critical value of the F distribution with (df1, df2) degrees of freedom at `level` (upper tail).
double fCritical(double df1, double df2, double level);
/// base + terms fitted to the noise-free recordings `truth` (the best of its starts) and linearised there, in noise
/// units (options' noise levels); unusable when no start converged.
LinearisedModel linearisedFit(const TireParams& base, const DiagnosisData& truth, const DetectabilityOptions& options,
                              const std::vector<Term>& terms);

/// The smallest effect of one term that the recordings would reveal (detectionLimits).
struct DetectionLimit {
  std::string term;       ///< library name
  std::string parameter;  ///< the size parameter searched ("" for turn_slip_orientation)
  double neutral = std::numeric_limits<double>::quiet_NaN();  ///< its no-effect value [unit]; NaN for sigma_T (inf)
  /// Parameter values at which the power reaches the wanted one, below and above the neutral value [unit]; NaN
  /// when that side is impossible (a bound) or the power is not reached within the parameter's bounds.
  double below = std::numeric_limits<double>::quiet_NaN();
  double above = std::numeric_limits<double>::quiet_NaN();
  double switch_power = std::numeric_limits<double>::quiet_NaN();  ///< turn_slip_orientation only [-]
  std::string note;  ///< why a side has no limit, or why the term is not applicable
};

/// Detection limits of every applicable term (and a note for the others) on `data`, whose measured values are
/// replaced by the base model at `w3_scale`, `mu_scale` plus each term. Uses options' noise levels, alpha_select,
/// candidates, model and solver. @throw std::invalid_argument for invalid options, power outside (0, 1), or
/// levels that are not > 0.
std::vector<DetectionLimit> detectionLimits(const TireParams& base, const DiagnosisData& data, double w3_scale,
                                            double mu_scale, double power, const DetectabilityOptions& options);

/// Power of an F test with (df1, df2) degrees of freedom at `level` against noncentrality lambda:
/// P(F'(df1, df2; lambda) > F_crit(level)). 1 for lambda > 1e4 (the computation is then needlessly slow).
double fTestPower(double lambda, double df1, double df2, double level);

}  // namespace diagnosis
}  // namespace tread_wear
