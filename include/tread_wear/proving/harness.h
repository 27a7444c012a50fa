#pragma once
/// @file harness.h
/// The proof of the diagnosis: generated cases (conceal.h) for every library term at several magnitudes and
/// noise levels, repeated with different seeds, plus no-effect controls; each case diagnosed (diagnosis.h) and
/// scored against its answer:
///   right      the explanation is exactly the hidden term (controls: "none")
///   parameter  the primary parameter is within 25% of the true one, measured as the effect:
///              |estimate - truth| <= 0.25 |truth - neutral| (neutral = the value without effect, e.g. gain 1,
///              q of the file); thermal_wear's sigma_T (no neutral value) relative to itself. Only scored when
///              the term was selected; turn_slip_orientation has none.
///   parameter, relative  the plain reading of "within 25%": |estimate - truth| <= 0.25 |truth| (looser than the
///              above where the neutral value is not 0: gain, q)
///   all three  right, parameter (effect reading) and improved in the same case
///   covered    the true primary parameter lies within 2 reported standard errors of the estimate (are the
///              uncertainties the tool reports honest? about 95% if they are); scored when the term was selected
///   improved   the held-out RMSER of every output the term affects is lower after than before
///   none       (controls) the verdict is "none"
///   false sensor  (cases whose hidden effect does not touch the side force: controls, thermal_wear,
///              surface_polishing) the verdict names a sensor term (sensor_gain, sensor_offset), i.e. a transducer
///              error on an output the effect leaves alone (issue 26's target: at most 5%)
///   empirical  (out-of-library cases, HarnessOptions::out_of_library) the diagnosis, whose library lacks the hidden
///              user-defined mechanism, gives an empirical term (empirical.h) in a covariate the mechanism reads,
///              with a lower held-out RMSER of the output it affects than the base model's
/// Design `drives` (drive_fleet.h): the effects are thermal_wear and rough_road (HarnessOptions::effects may
/// name either), diagnosed with the whole library. rough_road is in no library term: it is `right` when the
/// diagnosis gives an empirical term in rough_road_share (the covariate the effect reads) with a lower held-out
/// wear RMSER than the base model's (scored as `empirical` too, and as `improved`); its parameter is scored when the
/// empirical term is linear (b of wear x (1 + b (x - m)) against beta). Each outcome also records the drive
/// cells the diagnosis evaluated (ExtendedModel::evaluationPoints).
/// The recordings are generated at HarnessOptions::generator's preset (default `reference`, the converged grid),
/// finer than any preset the diagnosis chooses (auto goes up to `fine`), so that the solver's error is part of
/// every proof; a harness that generated with the diagnosing preset could not see it.
/// With HarnessOptions::information, each case also gets its detectability reference (detectability.h), computed
/// on the case's own noise-free recordings: the probability that a selector knowing the noise levels names the
/// hidden term. Its mean over the cases is the rate that the recordings allow, beside the rate measured. Likewise
/// for the parameter: the probability of the right explanation times that of an estimate within 25% of the effect,
/// 2 Phi(0.25 |effect| / SE) - 1 for an unbiased estimate with the reference's standard error SE.

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/proving/detectability.h"

namespace tread_wear {
namespace diagnosis {

struct HarnessCase {
  ConcealSpec spec;
  std::string magnitude_label;  ///< "default", "small", "large"
  bool out_of_library = false;  ///< diagnosed with the built-in library less the hidden term (scored: empirical)
};

struct HarnessOutcome {
  HarnessCase c;
  std::string explanation;
  bool right = false;
  bool named = false;          ///< right, or the hidden term is a close alternative of the explanation (diagnosis.h)
  bool sensor_scored = false;  ///< the hidden effect does not touch the side force (see above)
  bool false_sensor = false;   ///< and the verdict names a sensor term
  std::string preset;          ///< the diagnosis's preset after any escalation
  bool parameter_scored = false, parameter_ok = false, parameter_ok_relative = false;
  bool all_met = false;  ///< right, parameter_ok (when scored) and improved (when scored) together
  bool parameter_estimated = false, parameter_covered = false;  ///< the term was selected; truth within 2 SE
  bool improved_scored = false, improved = false;
  double estimate = std::numeric_limits<double>::quiet_NaN(), truth = std::numeric_limits<double>::quiet_NaN();
  double std_error = std::numeric_limits<double>::quiet_NaN();  ///< reported standard error of the estimate
  double cv_before[kNumOutputs] = {0.0, 0.0}, cv_after[kNumOutputs] = {0.0, 0.0};
  bool empirical_scored = false, empirical_ok = false;  ///< out-of-library case; its criterion met
  std::string empirical_covariate;                      ///< covariate of the empirical term given, "" for none
  bool information = false;                             ///< the reference below was computed
  Detectability reference;  ///< detectability of the hidden term on this case's noise-free recordings
  double reference_parameter_ok = std::numeric_limits<double>::quiet_NaN();  ///< probability, see above [-]
  std::string reference_error;     ///< why the reference could not be computed (the verdict still counts)
  double seconds = 0.0;            ///< generation, diagnosis and scoring [s]
  double diagnosis_seconds = 0.0;  ///< the diagnosis alone [s]
  std::size_t cells = 0;           ///< operating points the model evaluates per set of brush parameters [-]
  std::string error;               ///< non-empty when the case failed to run
};

struct HarnessOptions {
  std::string design = "table2";                  ///< a ConcealSpec design
  DriveFleet fleet;                               ///< the fleet of design drives
  int repeats = 5;                                ///< seeds per (effect, magnitude, noise), >= 1
  int control_repeats = 20;                       ///< no-effect controls per noise level, >= 0
  std::vector<double> wear_noise = {0.05, 0.10};  ///< wear RSD levels [-]
  double side_force_noise_n = 1.0;                ///< at wear RSD 5%; scaled with the wear noise level
  std::vector<std::string> effects;  ///< empty = every library term (design drives: thermal_wear and rough_road)
  bool two_magnitudes = true;        ///< small and large magnitude (else the default only)
  int jobs = 1;                      ///< worker threads
  bool information = false;          ///< also each case's detectability reference (about a third more time)
  /// Out-of-library cases: every case (controls too) is diagnosed with the built-in library less the hidden term,
  /// so that a hidden user-defined mechanism is one the library lacks (scored: empirical)
  bool out_of_library = false;
  std::uint64_t seed = 1000;
  DiagnosisOptions diagnosis;
  /// Preset that generates the recordings (with the diagnosis's orientation)
  Preset generator_preset = Preset::kReference;
};

/// The case list of a harness run. @throw std::invalid_argument for an effect without magnitudes (a user-defined
/// term without test magnitudes).
std::vector<HarnessCase> harnessCases(const HarnessOptions& options);
/// Scores one diagnosed case against its answer.
HarnessOutcome scoreCase(const HarnessCase& c, const ConcealAnswer& answer, const DiagnosisResult& result);
/// Generates, diagnoses and scores every case (in parallel with options.jobs threads).
std::vector<HarnessOutcome> runHarness(const TireParams& base, const HarnessOptions& options,
                                       std::ostream* progress = nullptr);
/// Success-rate table (Markdown) per effect, magnitude and noise level, plus totals.
std::string harnessTable(const std::vector<HarnessOutcome>& outcomes);
/// One CSV line per case.
std::string harnessCsv(const std::vector<HarnessOutcome>& outcomes);

}  // namespace diagnosis
}  // namespace tread_wear
