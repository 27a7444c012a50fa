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

#include <string>
#include <vector>

#include "tread_wear/diagnosis/detection_limits.h"

namespace tread_wear {
namespace diagnosis {

/// One verdict of the oracle and how often it is reached.
struct OracleVerdict {
  std::string verdict;       ///< library name or "none"
  double probability = 0.0;  ///< share of the noise draws [-]
};

struct Detectability {
  std::string hidden;   ///< library name, or "none"
  int terms_tried = 0;  ///< m: the candidate terms the data can show
  double lambda = 0.0;  ///< lambda_A [-]; 0 for none
  /// Power of the first-step F test of the hidden term [-]; NaN for none.
  double power = std::numeric_limits<double>::quiet_NaN();
  std::vector<OracleVerdict> verdicts;         ///< most likely first
  double expected_right = 0.0;                 ///< share of the verdicts that name the hidden term (or none) [-]
  std::vector<ReferenceParameter> parameters;  ///< of base + the hidden term; empty for none
};

/// The reference for recordings `truth` whose measured values are the noise-free outputs with `hidden` ("none"
/// or a library name) switched on. A hidden term that the data cannot show (termApplicable) has power 0.
/// @throw std::invalid_argument for invalid options, an unknown term, or fewer measured values than the models
/// need.
Detectability detectability(const TireParams& base, const DiagnosisData& truth, const std::string& hidden,
                            const DetectabilityOptions& options);

}  // namespace diagnosis
}  // namespace tread_wear
