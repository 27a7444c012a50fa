#pragma once
/// @file numerics_check.h
/// Is the brush model's discretisation error small against the measurement noise at the recorded conditions?
/// (issue 26, part 0a). The diagnosis fits its models at a resolution preset (wear_model.h); a preset's error is a
/// systematic, condition-dependent bias, and the tests of step 4 (diagnosis.h) cannot tell it from a missing term.
///
/// At a fitted point (a model's terms and parameter values), every recorded run is predicted at the preset and at
/// the `reference` preset, the model's converged grid (docs/performance.md: within 0.013% Fy and 0.016% W_r of the
/// CVODE solver on the rig). The solver error of run i, output o, is d_io = reference - preset, in units of the
/// noise model's sigma_io (noise_model.h). The fitted parameters absorb the part of d that their own directions
/// span (a uniform wear bias moves w3_scale, not a verdict), so the measure is what they cannot absorb:
///   lambda_num = | (I - P) W d |^2,   W = diag(1 / sigma),   P the projector onto the columns of W J,
/// J the Jacobian of the predictions in the fitted parameters (forward differences of 1% of each parameter's scale,
/// into the admissible range). lambda_num is the largest noncentrality that the solver error can give the F test
/// of any one-parameter term not yet in the model, i.e. the square of the largest shift, in standard errors, of
/// its test statistic. Criterion: lambda_num <= limit (default 1: a shift of at most one standard error, which at
/// the first selection step's level, 0.01 / 9, raises a null term's rejection probability from 0.11% to at most
/// 1.2%). Also reported per output: the RMS of d / sigma, the RMS and largest relative error |d / preset|, and
/// the unprojected |W d|^2.
/// Limits: the reference preset itself is not checked (nothing finer in the model); the Jacobian is linearised.
///
/// Drives (issue 36): when every run is a drive segment and the segments share more coarse cells than
/// NumericsSampling::first_sample_cells, d is estimated from a sample of the cells instead of predicting every
/// cell at `reference` (3.7 ms a cell: 20,000 cells cost over a minute per check). A segment's solver error is a
/// sum over its cells (ExtendedModel::coarseCellContributions), so a Poisson sample with inclusion probability
/// pi_c proportional to the cell's weighted contribution to the predictions (the largest ones taken with
/// certainty) gives the Horvitz-Thompson estimate d^ = sum over the sample of y_c / pi_c, y_c the cell's weighted
/// solver error per measured value, with covariance S = sum (1 - pi_c) / pi_c^2 y_c y_c^T. Then
/// |(I - P) W d| lies within |(I - P) W d^| +- q, q the `confidence` quantile of |(I - P) e|, e ~ N(0, S) (the
/// triangle inequality; q by a seeded Monte Carlo of the weighted chi-squares), so lambda_num lies in
/// [noncentrality_low, noncentrality_high] with at least that confidence. The check passes when the upper bound
/// is within the limit and fails when the lower bound is beyond it; otherwise the sample grows fourfold (the same
/// uniform draws, so the cells already compared stay in) until it decides or holds every cell (then exact).
/// The preset's own predictions and the Jacobian use every cell (they cost microseconds a cell).

#include <cstdint>
#include <string>
#include <vector>

#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/diagnosis/noise_model.h"

namespace tread_wear {
namespace diagnosis {

struct NumericsOutput {
  int values = 0;                  ///< measured values compared
  double rms_in_noise = 0.0;       ///< RMS of d / sigma [-]
  double rms_relative = 0.0;       ///< RMS of d / prediction at the preset [-]
  double max_relative = 0.0;       ///< largest |d / prediction| [-]
  double noncentrality_raw = 0.0;  ///< sum of (d / sigma)^2 over the output, before the projection [-]
};

/// How the solver error of drive segments is estimated (the file comment); part of DiagnosisOptions.
struct NumericsSampling {
  int first_sample_cells = 400;  ///< expected cells of the first sample; 0 = always every cell, >= 0
  double confidence = 0.95;      ///< of the interval of lambda_num that decides, in (0.5, 1)
  std::uint64_t seed = 36;       ///< of the uniform draws and the Monte Carlo (results do not depend on --jobs)
  bool validate(std::string* error) const;
};

struct NumericsCheck {
  bool checked = false;               ///< false for the reference preset (nothing finer to compare with)
  std::string at_model;               ///< label of the fitted model checked (termsLabel)
  Preset preset = Preset::kFast;      ///< the preset checked
  Preset finer = Preset::kReference;  ///< the preset it was compared with
  NumericsOutput outputs[kNumOutputs];
  double noncentrality = 0.0;  ///< lambda_num, after the projection [-]
  double limit = 1.0;          ///< the criterion [-]
  bool passed = true;
  int cells = 0;            ///< coarse drive cells of the data (0 for steady runs)
  int cells_compared = 0;   ///< of which evaluated at the finer preset (all of them unless sampled)
  bool sampled = false;     ///< lambda_num estimated from a sample of the cells (file comment)
  double confidence = 1.0;  ///< of [noncentrality_low, noncentrality_high]; 1 = exact
  double noncentrality_low = 0.0, noncentrality_high = 0.0;  ///< interval of lambda_num [-]
  double seconds = 0.0;                                      ///< wall time of the check [s]
};

/// Checks `model` at the parameter `values` (its layout) against the reference preset, with the noise model of
/// each output. @throw std::invalid_argument when the model cannot be evaluated there.
NumericsCheck checkNumerics(const TireParams& base, const DiagnosisData& data, const ExtendedModelOptions& options,
                            const std::vector<Term>& terms, const std::vector<double>& values,
                            const NoiseModel noise[kNumOutputs], double limit,
                            const NumericsSampling& sampling = NumericsSampling());

/// "solver error at fast: lambda 3.2 against the limit 1 (side force 1.1 sigma RMS, 1.2% RMS; wear ...)".
std::string numericsSummary(const NumericsCheck& check);

}  // namespace diagnosis
}  // namespace tread_wear
