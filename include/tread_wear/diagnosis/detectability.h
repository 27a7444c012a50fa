#pragma once
/// @file detectability.h
/// What recordings of a design can show at all: the information reference beside the diagnosis's success rates
/// (harness.h). Given the noise-free recordings of a hidden term A (conceal.h keeps them beside the noisy ones) and
/// the noise levels (side force sigma_F [N], additive; wear relative RSD s_W), residuals are measured in units of
/// the noise: (Fy - Fy_true) / sigma_F and (W / W_true - 1) / s_W.
///  - Noncentrality: lambda_A = the smallest residual sum of squares of the base model (w3_scale, mu_scale free) on
///    A's noise-free recordings: the part of the effect that the base model cannot absorb. For a small effect the
///    drop in residual sum of squares that A brings on noisy recordings is lambda_A plus chi-square noise (Seber
///    and Wild 2003, Sec 5.3, linearised).
///  - Power: the probability that the diagnosis's first-step F test of A against the base model (diagnosis.h, step
///    4: level alpha_select / m over the m terms tried; twice that level for a term whose no-effect value is a
///    bound, the boundary test) passes: P(F'(k_A, n - p_A; lambda_A) > F_crit), F' the noncentral F distribution
///    (Boost.Math), n the measured values, p_A the model's parameters, k_A those of the term.
///  - Oracle verdicts: the diagnosis's first selection step, with the runs weighted by the true noise levels, on
///    `draws` noise draws, each model linearised around its best fit to the noise-free recordings (Gauss-Newton:
///    on recordings truth + e its residual sum of squares is |(I - P_M)(r_M - e)|^2, r_M its noise-free residual,
///    P_M the projection on its Jacobian's columns; a one-parameter term on its no-effect bound may only move
///    inwards). Every applicable term is tested against the base model (F test and AICc drop, as the diagnosis);
///    of the eligible, the lowest AICc is the verdict (the diagnosis cross-validates the best three instead), else
///    "none". expected_right = the share of draws whose verdict is A ("none" for no hidden term). The diagnosis
///    estimates the noise levels and weights the error ratios of one output alike, so it can fall short of this
///    reference; being a probability per case, the reference has no draw-to-draw scatter, which the measured 0/1
///    outcomes have.
///  - Parameters: the standard errors of the hidden model's parameters at the truth, (J^T J)^-1 in noise units,
///    the precision that a fit with the true noise weights reaches (the diagnosis's HC3 errors estimate the same).
/// Limits: linearised (small effects); the first selection step only (no pairs).
///
/// Detection limits (detectionLimits): the same power calculation on the user's own recordings, for a `none`
/// verdict to say what it rules out. For each applicable term, its size parameter is moved away from the value at
/// which the term has no effect (both ways where both are possible) until the first-step F test reaches the
/// wanted power (0.8 by convention, Cohen 1988) against the calibrated base model, at the noise levels the
/// diagnosis estimated. The truth is the base model at its fitted levels plus the term; lambda comes from a full
/// (nonlinear) base fit to it, so large limits are not linearised. Conventions: thermal_wear is searched in sigma_T
/// with T0 at the coldest run (wear then rises over the observed temperatures); load_fluctuation's limit is the
/// multiple of the recorded load std; turn_slip_orientation is a switch, so it reports the power of the switch.

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
  double wear_noise_rsd = 0.05;    ///< relative wear noise s_W [-], > 0
  double side_force_noise_n = 1.0; ///< additive side-force noise sigma_F [N], > 0
  double alpha_select = 0.01;      ///< the diagnosis's family-wise level of the term tests (0, 1)
  double min_aicc_drop = 2.0;      ///< the diagnosis's AICc drop for an eligible term, >= 0
  int draws = 10000;               ///< noise draws of the oracle verdicts, >= 100
  std::uint64_t seed = 1;          ///< of the noise draws
  std::vector<Term> candidates;    ///< terms to try; empty = every applicable term (as the diagnosis)
  ExtendedModelOptions model;      ///< preset and orientation, as in the diagnosis
  LeastSquaresOptions solver;

  bool validate(std::string* error) const;
};

/// A parameter of the hidden term's model fitted to its own noise-free recordings (the truth), with the standard
/// error of its estimate on noisy recordings (linearised, known noise): the reference for the estimate's precision.
struct ReferenceParameter {
  std::string name;
  double value = 0.0;      ///< [unit of the parameter]
  double std_error = std::numeric_limits<double>::quiet_NaN();  ///< [unit]; NaN on a bound
};

/// One verdict of the oracle and how often it is reached.
struct OracleVerdict {
  std::string verdict;        ///< library name or "none"
  double probability = 0.0;   ///< share of the noise draws [-]
};

struct Detectability {
  std::string hidden;         ///< library name, or "none"
  int terms_tried = 0;        ///< m: the candidate terms the data can show
  double lambda = 0.0;        ///< lambda_A [-]; 0 for none
  /// Power of the first-step F test of the hidden term [-]; NaN for none.
  double power = std::numeric_limits<double>::quiet_NaN();
  std::vector<OracleVerdict> verdicts;  ///< most likely first
  double expected_right = 0.0;          ///< share of the verdicts that name the hidden term (or none) [-]
  std::vector<ReferenceParameter> parameters;  ///< of base + the hidden term; empty for none
};

/// The reference for recordings `truth` whose measured values are the noise-free outputs with `hidden` ("none"
/// or a library name) switched on. A hidden term that the data cannot show (termApplicable) has power 0.
/// @throw std::invalid_argument for invalid options, an unknown term, or fewer measured values than the models
/// need.
Detectability detectability(const TireParams& base, const DiagnosisData& truth, const std::string& hidden,
                            const DetectabilityOptions& options);

/// The smallest effect of one term that the recordings would reveal (detectionLimits).
struct DetectionLimit {
  std::string term;        ///< library name
  std::string parameter;   ///< the size parameter searched ("" for turn_slip_orientation)
  double neutral = std::numeric_limits<double>::quiet_NaN();  ///< its no-effect value [unit]; NaN for sigma_T (inf)
  /// Parameter values at which the power reaches the wanted one, below and above the neutral value [unit]; NaN
  /// when that side is impossible (a bound) or the power is not reached within the parameter's bounds.
  double below = std::numeric_limits<double>::quiet_NaN();
  double above = std::numeric_limits<double>::quiet_NaN();
  double switch_power = std::numeric_limits<double>::quiet_NaN();  ///< turn_slip_orientation only [-]
  std::string note;        ///< why a side has no limit, or why the term is not applicable
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
