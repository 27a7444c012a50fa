#include "tread_wear/model/wear_model.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "tread_wear/model/validation.h"

namespace tread_wear {

const char* presetName(Preset preset) {
  switch (preset) {
    case Preset::kFast: return "fast";
    case Preset::kStandard: return "standard";
    case Preset::kFine: return "fine";
    case Preset::kReference: return "reference";
  }
  return "unknown";
}

bool parsePreset(const std::string& name, Preset* preset) {
  for (Preset p : kAllPresets) {
    if (name == presetName(p)) {
      *preset = p;
      return true;
    }
  }
  return false;
}

const char* orientationName(TurnSlipOrientation orientation) {
  return orientation == TurnSlipOrientation::kLiteral ? "literal" : "flipped";
}

bool parseOrientation(const std::string& name, TurnSlipOrientation* orientation) {
  for (TurnSlipOrientation o : {TurnSlipOrientation::kLiteral, TurnSlipOrientation::kFlipped}) {
    if (name == orientationName(o)) {
      *orientation = o;
      return true;
    }
  }
  return false;
}

BrushOptions presetOptions(Preset preset, TurnSlipOrientation orientation) {
  // Where the element crosses the patch within one natural period (high speed), the patch response is
  // its entry transient: the leading half of the x grid is then graded 0.98 instead of 0.9 (road Fy
  // 1.5% -> 0.61% for standard, no cost: docs/performance.md, "Entry-transient grid"). There both presets
  // also march twice their strips, for the capture front in the shoulder band that sets Mz (road Mz 6.6% ->
  // 1.8% for standard, 18.7% -> 5.8% for fast; same section).
  constexpr double kEntryTransitPeriods = 1.0, kEntryGrading = 0.98;
  constexpr int kFastEntryStrips = 12, kStandardEntryStrips = 24, kFineEntryStrips = 64;
  BrushOptions o;
  o.orientation = orientation;
  switch (preset) {
    // Grids chosen from the accuracy study in docs/performance.md (errors measured, not assumed).
    case Preset::kFast:
      o.grid = {40, 6, 0.9, LateralRule::kGaussLegendre, kEntryTransitPeriods, kEntryGrading, kFastEntryStrips};
      o.turn_slip_iterations = 1;
      o.root_tolerance = 3e-2;
      break;
    case Preset::kStandard:
      o.grid = {60, 12, 0.9, LateralRule::kGaussShoulderPanels, kEntryTransitPeriods, kEntryGrading,
                kStandardEntryStrips};
      o.turn_slip_iterations = 1;
      o.root_tolerance = 3e-2;
      // Substeps where sliding is unstable (stick-slip bursts); the budget (as many substeps as grid
      // nodes) bounds the worst case at twice the fixed grid's nodes. Damping ratio 1 instead (level 2, budget
      // 1440) lowers the road grid's W_r maximum from 8.5% to 4.9% at a p99 of 84 instead of 48 us, above the
      // 60 us target (docs/performance.md, "How the marcher is fast").
      o.refinement = {3, 720, 0.5, 0.0};
      break;
    case Preset::kFine:
      // Twice standard's x steps (the Mz error constant at 5-20 m/s), twice its strips (the W_r shoulder
      // error at 5 m/s), 64 strips on the entry-transient grid (the capture front at 40 m/s), and substeps
      // wherever sliding is underdamped (damping ratio 1), at resolution 0.25: the release of the deflection
      // at the trailing edge and the stick-slip bursts at low speed (docs/performance.md, "fine").
      o.grid = {120, 24, 0.9, LateralRule::kGaussShoulderPanels, kEntryTransitPeriods, kEntryGrading, kFineEntryStrips};
      o.turn_slip_iterations = 1;
      o.root_tolerance = 3e-2;
      o.refinement = {4, 8000, 0.25, 1.0};
      // Its short substeps meet near-tangent slide roots (velocity-weakening branch) at extreme slip and
      // low speed, where the safeguarded Newton iteration converges linearly: 42 iterations at Fz 210 N,
      // kappa -0.62, V 0.25 m/s (the 40th iterate gives the same W_r to 6 digits).
      o.max_root_iterations = 60;
      break;
    case Preset::kReference:
      o.grid = {1600, 64, 0.8, LateralRule::kSineMidpoint};
      o.turn_slip_iterations = 3;
      o.root_tolerance = 1e-7;
      break;
  }
  return o;
}

bool WearModelOptions::validate(std::string* error) const {
  if (!(min_speed_mps > 0.0) || !std::isfinite(min_speed_mps))
    return failValidation(error, "min_speed_mps", min_speed_mps, "finite and > 0");
  if (!(min_rolling_speed_mps > 0.0 && min_rolling_speed_mps <= min_speed_mps))
    return failValidation(error, "min_rolling_speed_mps", min_rolling_speed_mps, "in (0, min_speed_mps]");
  if (!(time_budget_s >= 0.0) || !std::isfinite(time_budget_s))
    return failValidation(error, "time_budget_s", time_budget_s, "finite and >= 0 (0 = no budget)");
  if (budget_probe_interval < 1) return failValidation(error, "budget_probe_interval", budget_probe_interval, ">= 1");
  if (!(timing_smoothing > 0.0 && timing_smoothing <= 1.0))
    return failValidation(error, "timing_smoothing", timing_smoothing, "in (0, 1]");
  return true;
}

WearModel::WearModel(const TireParams& params, const WearModelOptions& options)
    : params_(params),
      options_(options),
      wanted_(options.preset),
      budget_s_(options.time_budget_s),
      active_(options.preset) {
  std::string error;
  if (!options.validate(&error)) throw std::invalid_argument("invalid wear model options: " + error);
  for (Preset p : kAllPresets)
    solvers_[static_cast<int>(p)] = std::make_unique<BrushWearModel>(params, presetOptions(p, options.orientation));
  timing_s_.fill(std::numeric_limits<double>::quiet_NaN());
}

void WearModel::setTimeBudget(double seconds) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds))
    throw std::invalid_argument("time budget = " + std::to_string(seconds) + " s: must be finite and >= 0");
  budget_s_ = seconds;
}

void WearModel::recordTiming(Preset preset, double seconds) const {
  double& t = timing_s_[static_cast<int>(preset)];
  t = std::isnan(t) ? seconds : t + options_.timing_smoothing * (seconds - t);
}

Preset WearModel::choosePreset() const {
  if (budget_s_ <= 0.0) return wanted_;
  int p = static_cast<int>(wanted_);
  // Unmeasured presets count as fitting, so that each gets measured once.
  while (p > 0 && timing_s_[p] > budget_s_) --p;
  if (p < static_cast<int>(wanted_) && since_probe_ >= options_.budget_probe_interval) ++p;  // probe finer
  return static_cast<Preset>(p);
}

bool WearModel::fitsFields(Preset preset, const PatchFields& fields) const {
  const BrushWearModel& s = solver(preset);
  // Sized by resize(nodesX(), strips()); an evaluation may since have set n_strips to a narrower grid's.
  return fields.n_x_nodes == s.nodesX() && fields.y_m.size() == static_cast<size_t>(s.strips()) &&
         fields.pressure_pa.size() == static_cast<size_t>(s.nodesX()) * static_cast<size_t>(s.strips());
}

OperatingPoint lowSpeedPoint(const OperatingPoint& op, const WearModelOptions& options, bool* low_speed) {
  OperatingPoint eval_op = op;
  bool low = false;
  if (op.speed_mps < options.min_speed_mps) {
    eval_op.speed_mps = options.min_speed_mps;
    low = true;
  }
  const double vx = eval_op.longitudinalSpeed();  // > 0: speed > 0 and |alpha| < pi/2
  if (eval_op.rollingSpeed() < options.min_rolling_speed_mps) {
    eval_op.slip_ratio = options.min_rolling_speed_mps / vx - 1.0;
    low = true;
  }
  if (low_speed != nullptr) *low_speed = low;
  return eval_op;
}

namespace {

// Every field of the point, bit for bit (NaN temperatures equal, -0 and +0 apart): the solver's input is then the
// same, and so is its result. A new field of OperatingPoint must be a double, or this comparison must change.
static_assert(std::is_trivially_copyable_v<OperatingPoint> && sizeof(OperatingPoint) == 6 * sizeof(double),
              "samePoint compares OperatingPoint's bytes: every field must be one of its six doubles");
bool samePoint(const OperatingPoint& a, const OperatingPoint& b) {
  return std::memcmp(&a, &b, sizeof(OperatingPoint)) == 0;
}

}  // namespace

EvalStatus WearModel::evaluate(const OperatingPoint& op, WearResult* result, PatchFields* fields) const {
  if (!op.validate(nullptr)) return EvalStatus::kInvalidInput;
  Preset preset = choosePreset();
  if (fields != nullptr && !fitsFields(preset, *fields)) {
    // Local fields are laid out on one preset's grid: use that preset for this call, whatever the budget.
    for (Preset p : kAllPresets)
      if (fitsFields(p, *fields)) preset = p;
    if (!fitsFields(preset, *fields)) fields = nullptr;  // sized for no preset: left untouched
  }
  const BrushWearModel& solver = *solvers_[static_cast<int>(preset)];
  bool low_speed = false;
  const OperatingPoint eval_op = lowSpeedPoint(op, options_, &low_speed);
  const EvalStatus status = low_speed ? EvalStatus::kLowSpeed : EvalStatus::kOk;
  const auto start = std::chrono::steady_clock::now();
  const bool reusable = budget_s_ == 0.0 && fields == nullptr;  // a budget times every solve; fields need one
  reused_ = reusable && has_last_ && last_preset_ == preset && samePoint(eval_op, last_op_);
  if (reused_) {
    *result = last_result_;
  } else {
    solver.evaluate(eval_op, result, fields);
    if (reusable) {
      has_last_ = true;
      last_op_ = eval_op;
      last_preset_ = preset;
      last_result_ = *result;
    }
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status == EvalStatus::kLowSpeed) result->wear_rate_kg_per_s = result->wear_rate_kg_per_m * op.speed_mps;

  if (static_cast<int>(preset) > static_cast<int>(active_)) since_probe_ = 0;  // a probe or a recovery
  active_ = preset;
  if (budget_s_ > 0.0) {
    recordTiming(preset, elapsed);
    if (preset != wanted_) {
      ++degraded_count_;
      ++since_probe_;
    } else {
      since_probe_ = 0;
    }
  }
  return status;
}

}  // namespace tread_wear
