#pragma once
/// @file empirical.h
/// Empirical terms for what the library lacks (issue 26): when the diagnosis finds a mismatch that no library term
/// explains (verdict "unexplained") and the residuals follow a located covariate, a small family of empirical terms
/// in that covariate is fitted on the affected output, with the same selection as the library terms (diagnosis.h,
/// step 4: partial F test, AICc, held-out error over the same folds). They describe the recordings; they are not
/// physics, and the verdict stays "unexplained".
///
/// The family, for a numeric covariate x with mean m over the runs and half-width d = max |x - m| (generated as
/// user-defined mechanisms, user_mechanisms.h, evaluated after the model):
///   linear           output (1 + b (x - m))                     |b| <= 0.9 / d
///   quadratic        output (1 + b1 (x - m) + b2 (x - m)^2)     |b1| <= 0.45 / d, |b2| <= 0.45 / d^2
///   log_linear       output exp(b (x - m))                      |b| <= ln(10) / d
///   saturating_step  output (1 + a (1 - exp(-(x - x_min) / tau)))   sequence covariates only (run order,
///                    cumulative sliding): a in [-0.9, 2], tau in [range / 20, 2 range] (log scale)
///   group_offsets    output (1 + d_g [cycle_id == g]) for every surface cycle g but the first (whose level w3_scale
///                    carries): the one categorical covariate with a number an expression can read; d_g in [-0.9, 2]
/// The bounds keep the factor within 0.1 and 1.9 over the recorded range (within a factor 10 for log_linear, and for
/// the step up to a tripling): wide enough for any effect a rig would leave unexplained, narrow enough that the
/// output stays positive. Parameters are per unit of the covariate as recorded (e.g. 1/% for humidity_percent).
/// The covariates: the significant located effects in order of their p-value whose covariate an expression can read
/// (an operating variable, a numeric recorded column, or cycle_id; not the predicted output level, not another
/// categorical one such as condition_id: the result says why), up to three; each one's family goes through its own
/// selection (its own Bonferroni) until a term is accepted. The numeric covariates come first, cycle offsets only
/// when none of theirs is accepted: a covariate constant within each cycle (humidity per cycle) is judged by the
/// data's scheme, which holds out whole cycles (or brands, tests: data.h, holdOutGroups), and one parameter in it
/// beats five offsets that cannot predict a cycle held out whole. Held-out error: the data's scheme, except for the
/// cycle offsets, whose held-out error is leave one run out; they describe the recorded cycles only (the summary says
/// so).
/// Thread safety: the family joins the calling thread's library only (extensions.h, setThreadLibrary).

#include <string>
#include <vector>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/extensions.h"

namespace tread_wear {
namespace diagnosis {

struct DiagnosisOptions;
struct DiagnosisResult;

/// A fitted parameter of an empirical term.
struct EmpiricalParameter {
  std::string name;
  double value = 0.0;      ///< [unit]
  double std_error = 0.0;  ///< [unit]; NaN at a bound
  std::string unit;        ///< e.g. "1/%", "1/run"
};

/// The empirical term the selection accepted.
struct EmpiricalTerm {
  std::string name;  ///< e.g. "empirical_linear_humidity_percent"
  std::string form;  ///< linear, quadratic, log_linear, saturating_step, group_offsets
  std::string covariate;
  Output output = Output::kWear;
  double centre = 0.0;     ///< m, the covariate's mean over the runs [unit of the covariate]; 0 for group offsets
  std::string expression;  ///< as fitted (muparser syntax, `output` = the model's value)
  std::vector<EmpiricalParameter> parameters;
  double rmser_before = 0.0, rmser_after = 0.0;        ///< in sample, of the affected output [-]
  double cv_rmser_before = 0.0, cv_rmser_after = 0.0;  ///< held out, of the affected output [-]
  std::string cv_scheme;                               ///< of the held-out errors
  std::vector<double> prediction;                      ///< the output per run with the term, as accepted [N or kg/m]
  double p_value = 1.0;                                ///< partial F test against the base model
  double delta_aicc = 0.0;  ///< AICc of the base model minus the term's (> 0: the term is better supported)
};

struct EmpiricalResult {
  bool attempted = false;               ///< the verdict was "unexplained" and the step enabled
  std::vector<std::string> covariates;  ///< covariates whose families were tried, in order
  std::string covariate;                ///< the accepted term's covariate ("" for none)
  Output output = Output::kWear;        ///< the accepted term's output
  std::vector<std::string> family;      ///< names of the terms tried
  std::vector<EmpiricalTerm> terms;     ///< the accepted term (at most one), empty if none
  std::string reason;                   ///< why no term was accepted or none tried; "" when one was
  std::vector<std::string> log;         ///< the selection step in words
};

/// Builds the empirical family in `covariate` on `output` (names, parameters, expressions as above; `term` unset).
/// Returns an empty family, with *why_not saying why, when the data lack the covariate, it is categorical or not
/// readable by an expression, or it has no variance on the runs.
std::vector<TermInfo> empiricalFamily(const DiagnosisData& data, const std::string& covariate, Output output,
                                      std::string* why_not);

/// After a diagnosis whose verdict is "unexplained": the families of the located covariates (above), each selected
/// by a diagnosis restricted to it (one term, the options' levels and solver). Not attempted for any other verdict.
EmpiricalResult fitEmpiricalTerms(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options,
                                  const DiagnosisResult& result);

/// "wear x (1 + b (humidity_percent - 50.1)), b = -0.0081 +- 0.0012 1/%, held-out wear RMSER 12.3% -> 6.1%"
std::string empiricalSummary(const EmpiricalTerm& term);

}  // namespace diagnosis
}  // namespace tread_wear
