#pragma once
/// @file wear_model.h
/// The per-wheel wear model the node, the replay and the planner service call: the brush wear model
/// (brush_wear_model.h) at a resolution preset, with a defined behaviour at low speed and a time budget.
///
/// Low-speed convention (docs/performance.md):
/// - Below WearModelOptions::min_speed_mps (including V = 0) the model is evaluated at min_speed_mps
///   with the same slips; forces are those of that point, wear per distance W_r is held at its value
///   there, and wear per time is W_r V with the true V, so it goes to zero linearly at standstill (no
///   rolling, no sliding) and is continuous at the threshold. Status kLowSpeed.
/// - The rolling speed V_r = V_x (1 + kappa) goes to 0 as kappa -> -1 (locked wheel) at any V: the slip
///   ratio is raised so that V_r >= min_rolling_speed_mps (the element transit time 2a/V_r stays
///   finite); the slip speed is then V_x - V_r, within min_rolling_speed_mps of the locked value.
///   Status kLowSpeed.
/// Nothing divides by the speed.
///
/// Time budget: with WearModelOptions::time_budget_s > 0 (or setTimeBudget()), each evaluation uses the
/// finest preset, up to the wanted one, whose measured time fits the budget. Times are measured with a
/// steady clock around every evaluation and smoothed per preset (exponentially weighted mean); a preset
/// not measured yet is assumed to fit (so it gets measured once). While degraded, every
/// budget_probe_interval evaluations one evaluation probes the next finer preset, so that the model
/// climbs back when the machine gets quieter. degraded() and degradedCount() report coarser-than-wanted
/// evaluations (the node publishes them as a diagnostic). recordTiming() injects a time (tests, seeding).
/// WearModel is not thread-safe (the timing state changes in the const evaluate()): one per thread.
///
/// Repeated points: without a time budget and without local fields, an evaluation at the same point (every field
/// bit for bit, after the low-speed convention) and preset as the last one returns that one's solver result
/// without solving again: a standstill, or inputs held between their samples when the wheel steps faster than they
/// arrive. The result is the solver's own, so nothing changes but the cost (lastEvaluationReused()).

#include <array>
#include <iterator>
#include <memory>
#include <string>

#include "tread_wear/model/brush_wear_model.h"

namespace tread_wear {

/// Resolution presets, coarse to fine (the time budget degrades in this order). Errors against the reference
/// and times per evaluation: docs/performance.md. `standard` is the real-time default; `fine` meets the
/// accuracy bounds of issue 4 on the whole rig and road grids at about 4 times its cost (offline replay,
/// calibration, low-speed manoeuvres); `reference` is the converged grid of the model spec.
enum class Preset { kFast = 0, kStandard = 1, kFine = 2, kReference = 3 };
inline constexpr Preset kAllPresets[] = {Preset::kFast, Preset::kStandard, Preset::kFine, Preset::kReference};
/// "fast, standard, fine or reference", for messages that list the names.
inline constexpr const char* kPresetChoices = "fast, standard, fine or reference";

/// "fast", "standard", "fine" or "reference".
const char* presetName(Preset preset);
/// Parses a preset name; false (and *preset untouched) for an unknown name.
bool parsePreset(const std::string& name, Preset* preset);
/// "literal" or "flipped": the one spelling of the turn-slip orientation in configuration files and tools.
const char* orientationName(TurnSlipOrientation orientation);
/// Parses an orientation name; false (and *orientation untouched) for an unknown name.
bool parseOrientation(const std::string& name, TurnSlipOrientation* orientation);
/// Grid and solver options of a preset.
BrushOptions presetOptions(Preset preset, TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral);

struct WearModelOptions {
  Preset preset = Preset::kStandard;  ///< finest preset wanted
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;
  double min_speed_mps = 0.1;            ///< low-speed threshold [m/s], > 0
  double min_rolling_speed_mps = 0.01;   ///< floor of the rolling speed V_r [m/s], in (0, min_speed_mps]
  double time_budget_s = 0.0;            ///< time budget per evaluation [s], >= 0; 0 = no budget
  int budget_probe_interval = 200;       ///< evaluations between probes of a finer preset while degraded, >= 1
  double timing_smoothing = 0.1;         ///< weight of a new time in the per-preset mean [-], (0, 1]

  bool validate(std::string* error) const;
};

enum class EvalStatus {
  kOk = 0,
  kLowSpeed = 1,     ///< speed below min_speed_mps: the low-speed convention applied
  kInvalidInput = 2  ///< the operating point failed validate(); result untouched
};

/// The point the model is evaluated at for the operating point `op` under the low-speed convention above (speed
/// raised to min_speed_mps, slip ratio raised so that V_r >= min_rolling_speed_mps); *low_speed (optional) says
/// whether either applied. W_r there, times op's own speed, is the wear per time WearModel::evaluate() returns.
OperatingPoint lowSpeedPoint(const OperatingPoint& op, const WearModelOptions& options, bool* low_speed = nullptr);

class WearModel {
 public:
  static constexpr int kPresets = static_cast<int>(std::size(kAllPresets));

  /// @throw std::invalid_argument naming the field for invalid parameters or options.
  WearModel(const TireParams& params, const WearModelOptions& options);

  /// Evaluates at the wanted preset, or the finest that fits the time budget; allocates nothing.
  /// Local fields, if requested, must be sized for one preset's grid (fields->resize(solver(p).nodesX(),
  /// solver(p).strips())): that call then uses preset p whatever the budget; fields sized for no preset
  /// are left untouched.
  EvalStatus evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields = nullptr) const;

  /// Sets the wanted (finest) preset.
  void setPreset(Preset preset) { wanted_ = preset; active_ = preset; }
  /// Preset used by the last evaluation (the wanted one before any evaluation).
  Preset activePreset() const { return active_; }
  Preset wantedPreset() const { return wanted_; }
  /// Sets the time budget per evaluation [s]; 0 disables it. @throw std::invalid_argument if < 0 or NaN.
  void setTimeBudget(double seconds);
  double timeBudget() const { return budget_s_; }
  /// True if the last evaluation used a coarser preset than the wanted one.
  bool degraded() const { return active_ != wanted_; }
  /// Number of evaluations that used a coarser preset than the wanted one.
  long degradedCount() const { return degraded_count_; }
  /// True if the last evaluation reused the result of the one before (the same point and preset; see above).
  bool lastEvaluationReused() const { return reused_; }
  /// Smoothed measured time of a preset [s]; NaN if not measured yet.
  double timing(Preset preset) const { return timing_s_[static_cast<int>(preset)]; }
  /// Feeds one measured evaluation time [s] of a preset into its smoothed time.
  void recordTiming(Preset preset, double seconds) const;
  /// The preset the next evaluation would use under the budget (the wanted one without a budget).
  Preset choosePreset() const;

  const BrushWearModel& solver(Preset preset) const { return *solvers_[static_cast<int>(preset)]; }
  const TireParams& params() const { return params_; }
  const WearModelOptions& options() const { return options_; }

 private:
  bool fitsFields(Preset preset, const PatchFields& fields) const;

  TireParams params_;
  WearModelOptions options_;
  Preset wanted_;
  double budget_s_;
  std::array<std::unique_ptr<BrushWearModel>, kPresets> solvers_;
  // Timing state, updated by the const evaluate() (see the file comment on thread safety).
  mutable Preset active_;
  mutable std::array<double, kPresets> timing_s_;
  mutable long degraded_count_ = 0;
  mutable long since_probe_ = 0;
  // The last solved point (low-speed convention applied), its preset and the solver's result (repeated points).
  mutable bool has_last_ = false;
  mutable bool reused_ = false;
  mutable OperatingPoint last_op_;
  mutable Preset last_preset_ = Preset::kStandard;
  mutable WearResult last_result_;
};

}  // namespace tread_wear
