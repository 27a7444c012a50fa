#pragma once
/// @file diagnosis.h
/// Mismatch diagnosis: where the base model and the recordings disagree, which physics is missing, and how much
/// better the model gets with it (issue 7). Steps:
///  0. Numerics (numerics_check.h): at the base fit and at the final model, the preset's solver error at the
///     recorded conditions must be small against the noise model's sigma (lambda_num <= numerics_limit). With
///     auto_preset a failed check escalates to the next finer preset (fast -> standard -> fine) and the diagnosis
///     starts again; beyond max_auto_preset it refuses (DiagnosisError). A given preset is kept and its failed
///     check is reported (numerics_warning).
///  1. Weights. Residuals are predicted - measured divided by the noise model's sigma (noise_model.h) at the
///     measured value: each output's kind (additive, relative, combined) is selected by AICc on the repeats
///     (enough of them over a range of levels), else on the base fit's residuals, or given (noise_kind). Its size
///     is the current model's weighted RMS (floors: the RMS of sigma/|y| at least 0.5% side force, 1% wear), set
///     after the base fit and after every accepted term, so that each F test compares models under one weighting
///     in which both outputs' residuals have about unit variance. A relative model gives the error ratios of Eq 24
///     divided by one scale, the weighting before issue 26.
///  2. Base fit: w3_scale and mu_scale (extensions.h) by bounded least squares (least_squares.h).
///  3. Locate: the base residuals of each output (standardised by the noise model) against every covariate
///     (data.h) and against the predicted output itself (a sensor gain or offset follows it): Spearman's rho with
///     the OLS slope and the change over the observed range for numeric covariates, eta^2 and the largest group
///     difference for categorical ones (both in error-ratio points), permutation p-values, Holm-adjusted over all
///     tests of both outputs (family-wise alpha_locate).
///  4. Explain: forward selection over the library (built-in and user-defined terms alike). At each step every
///     applicable term not yet in the model is
///     added and fitted (starting from the current solution; thermal_wear from three starts); a term is eligible
///     when its partial F test against the current model has p < alpha_select / (terms tried) (Bonferroni) and
///     AICc drops by at least min_aicc_drop; of the eligible, up to max_cv_candidates with the lowest AICc are
///     cross-validated (leave one cycle out, else one condition, else one run; folds start from the full-data
///     solution) and the one with the lowest held-out error is accepted if it beats the current model's held-out
///     error. A term that extends an explanation (the second of a pair) must beat it significantly: one-sided
///     Wilcoxon signed-rank test over the runs' paired held-out losses, p < alpha_select. Stops after max_terms
///     terms (pairs by default) or when nothing is accepted.
///  5. Verdict: explanation = the accepted terms ("a+b"); "unexplained" when the locating tests found a
///     significant mismatch but no term was accepted (the covariates the residual follows are listed); "none"
///     when neither found anything. mismatch_found is true unless the verdict is "none". Close alternatives: the
///     eligible candidates of an accepting step whose AICc is less than min_aicc_drop above the accepted model's,
///     i.e. not substantially worse supported (Burnham and Anderson's Delta AICc < 2): the recordings cannot tell them
///     from the explanation (a sensor gain and a sensor offset, where the design has few low-slip runs).
///  Empirical terms (empirical.h): with the verdict "unexplained", a family of empirical terms in the top located
///     covariate goes through the same selection; an accepted one is reported beside the verdict, as empirical.
///  6. Detection limits (detection_limits.h): for each applicable term, the smallest effect that step 4's first F test
///     would find with probability detection_power, added to the calibrated base model, at the noise the final
///     model leaves (side force in N, wear relative; dof-corrected, floored as the weights). They say what a
///     `none` rules out.
/// Limits: the F test and AICc assume independent, roughly normal weighted residuals; with few runs (the paper's
/// nine means) they are indicative only, which the report says.

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/detection_limits.h"
#include "tread_wear/diagnosis/empirical.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/diagnosis/noise_model.h"
#include "tread_wear/diagnosis/numerics_check.h"
#include "tread_wear/fitting/least_squares.h"

namespace tread_wear {
namespace diagnosis {

/// Where a running diagnosis is (DiagnosisOptions::progress), called on the diagnosing thread.
struct DiagnosisProgress {
  std::string step;               ///< e.g. "base fit", "numerics check", "selection step 1"
  Preset preset = Preset::kFast;  ///< the preset being diagnosed at
  long cells_evaluated = 0;       ///< brush evaluations of runs and drive cells since the diagnosis started
  int terms_tried = 0;            ///< in the current selection step
  int terms_in_step = 0;          ///< terms the current selection step fits (0 outside the selection)
  double elapsed_s = 0.0;         ///< since the diagnosis started [s]
  double step_left_s = -1.0;      ///< estimated time left in the current selection step [s]; < 0 when unknown
};

/// Wall time of one step of a diagnosis (DiagnosisResult::timings).
struct StepTiming {
  std::string step;               ///< "base fit", "numerics check at 'none'", "selection step 1", ...
  Preset preset = Preset::kFast;  ///< the preset it ran at
  double seconds = 0.0;           ///< wall time [s]
  long cells_evaluated = 0;       ///< brush evaluations in it
};

struct DiagnosisOptions {
  ExtendedModelOptions model;  ///< preset (the first one tried with auto_preset) and base orientation
  bool auto_preset = true;     ///< escalate while the numerics check fails (step 0); false: keep model.preset
  Preset max_auto_preset = Preset::kFine;  ///< finest preset auto_preset may choose, >= model.preset
  double numerics_limit = 1.0;             ///< largest lambda_num of the solver error (numerics_check.h), > 0
  NumericsSampling numerics_sampling;      ///< drives: the check on a sample of the cells (numerics_check.h)
  /// Noise model kind of each output (side force, wear); unset = selected by AICc (step 1)
  std::optional<NoiseKind> noise_kind[kNumOutputs];
  double alpha_locate = 0.01;    ///< family-wise error rate of the locating tests (Holm) (0, 1)
  double alpha_select = 0.01;    ///< family-wise error rate of the term tests per step (Bonferroni), and the
                                 ///< level of the pair step's held-out rank test (0, 1)
  double min_aicc_drop = 2.0;    ///< AICc must drop by at least this to make a term eligible, >= 0
  int max_terms = 2;             ///< largest combination (2 = pairs), >= 0
  int max_cv_candidates = 3;     ///< eligible terms cross-validated per step, >= 1
  int permutations = 9999;       ///< per locating test, >= 99
  std::uint64_t seed = 7;        ///< permutation seed
  std::vector<Term> candidates;  ///< terms to try (repeats count once); empty = the whole library
  LeastSquaresOptions solver;    ///< least-squares settings
  /// Power at which the detection limits (step 6) are set, in (0, 1); 0 = not computed (they cost about as much
  /// as the selection)
  double detection_power = 0.8;
  /// Fit empirical terms (empirical.h) when the verdict is "unexplained"
  bool empirical = true;
  /// Called at each step and after each term fitted (progress on stderr in tread_wear_diagnose); empty = none
  std::function<void(const DiagnosisProgress&)> progress;

  DiagnosisOptions();
  bool validate(std::string* error) const;
};

/// One locating test.
struct LocatedEffect {
  Output output = Output::kSideForce;
  std::string covariate;
  std::string kind;  ///< operating region, sequence, recorded, output level
  bool categorical = false;
  double rho = 0.0;    ///< numeric: Spearman rho of the relative residual over the covariate [-]
  double slope = 0.0;  ///< numeric: OLS slope [1/unit of the covariate]
  /// numeric: slope times range; categorical: largest group difference [-] (0.05 = 5 points of error ratio)
  double effect = 0.0;
  double eta_squared = 0.0;  ///< categorical: between-group share of variance [-]
  double p_value = 1.0;      ///< permutation p-value
  double p_adjusted = 1.0;   ///< Holm-adjusted
  bool significant = false;  ///< p_adjusted < alpha_locate
};

/// A fitted model (base plus terms).
struct FittedModel {
  std::vector<Term> terms;
  std::string label;  ///< termsLabel(terms)
  LeastSquaresSummary summary;
  Prediction prediction;
  bool usable = false;
  double rss = 0.0;     ///< weighted residual sum of squares
  int n_residuals = 0;  ///< measured values fitted
  int k = 0;            ///< free parameters (+1 for the orientation switch)
  double aicc = 0.0, bic = 0.0;
  double rmser[kNumOutputs] = {0.0, 0.0};  ///< in sample [-]; NaN when the output is not measured
  bool cv_done = false;
  double cv_rmser[kNumOutputs] = {0.0, 0.0};  ///< held out [-]
  double cv_score = 0.0;                      ///< mean weighted held-out squared residual
  /// per run: weighted held-out squared residuals summed over its outputs; NaN if none
  std::vector<double> cv_run_loss;
  double p_vs_parent = 1.0;  ///< partial F test against the model it extends
  /// One-sided Wilcoxon signed-rank p of its per-run held-out losses against the parent's; computed for the best
  /// candidate of a step that extends an explanation (NaN otherwise)
  double p_held_out = std::numeric_limits<double>::quiet_NaN();
  std::string parent;  ///< label of that model
  bool eligible = false;
};

/// An eligible candidate that the recordings support about as well as the model accepted at its step.
struct CloseAlternative {
  std::string model;        ///< label of the candidate, e.g. "sensor_offset"
  std::string instead_of;   ///< label of the model accepted at that step
  double delta_aicc = 0.0;  ///< candidate's AICc minus the accepted model's, < min_aicc_drop [-] (negative: a
                            ///< lower AICc, accepted model chosen by its held-out error)
};

struct DiagnosisResult {
  Preset preset = Preset::kFast;                ///< the preset of this result (after any escalation)
  std::vector<NumericsCheck> numerics;          ///< every solver-error check, in order (step 0)
  std::string numerics_decision;                ///< in words: the preset kept or escalated, and why
  std::string numerics_warning;                 ///< non-empty when a given preset failed its check
  NoiseSelection noise[kNumOutputs];            ///< each output's noise model as selected (or given) in step 1
  NoiseModel weights[kNumOutputs];              ///< the noise models of the last step's weights
  double pure_error[kNumOutputs] = {0.0, 0.0};  ///< pooled relative spread of repeats [-]; NaN without repeats
  int pure_error_dof[kNumOutputs] = {0, 0};     ///< its degrees of freedom
  std::string cv_scheme;
  std::vector<std::string> skipped_terms;  ///< "name: why" for terms the data cannot show
  FittedModel base;
  std::vector<FittedModel> tried;  ///< every extended model fitted, in order
  FittedModel final_model;
  std::vector<LocatedEffect> located_before;   ///< tests on the base residuals (sorted by p)
  std::vector<std::string> not_located;        ///< "output: why" for outputs without locating tests
  std::vector<LocatedEffect> located_after;    ///< the same tests on the final model's residuals
  std::vector<std::string> not_located_after;  ///< not_located for the final model
  bool mismatch_found = false;
  std::string explanation;  ///< library name, "a+b", "none" or "unexplained"
  std::vector<std::string> unexplained_covariates;
  std::vector<CloseAlternative> close_alternatives;  ///< of every accepting step (step 5 above)
  EmpiricalResult empirical;                         ///< empirical terms, with the verdict "unexplained"
  double side_force_noise_n = 0.0;               ///< noise the final model leaves: side force [N]; NaN if not measured
  double wear_noise_rsd = 0.0;                   ///< and wear, relative [-] (step 6); NaN if not measured
  double detection_power = 0.0;                  ///< power of the detection limits [-]
  std::vector<DetectionLimit> detection_limits;  ///< step 6; empty when not computed
  std::vector<std::string> log;                  ///< the selection steps in words
  std::vector<StepTiming> timings;               ///< every step, in order, over all presets tried
  double seconds = 0.0;                          ///< wall time of the whole diagnosis [s]
};

/// The detectability settings (detection_limits.h) that match a diagnosis's: its selection level, AICc drop,
/// candidates, model and solver, at the given noise levels (relative wear RSD [-], side force [N]).
DetectabilityOptions detectabilityOptions(const DiagnosisOptions& diagnosis, double wear_noise_rsd,
                                          double side_force_noise_n);

/// Runs the whole diagnosis. @throw std::invalid_argument for invalid options or parameters; DiagnosisError for an
/// applicable user-defined term that does not reduce to the model at its no-effect values (user_mechanisms.h).
DiagnosisResult diagnose(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options);

/// Relative residuals predicted/measured - 1 of one output (NaN where not measured).
std::vector<double> relativeResiduals(const DiagnosisData& data, const Prediction& prediction, Output output);

/// Value of a named parameter in a fitted model; NaN when absent.
double fittedValue(const FittedModel& model, const std::string& name, double* std_error = nullptr);

}  // namespace diagnosis
}  // namespace tread_wear
