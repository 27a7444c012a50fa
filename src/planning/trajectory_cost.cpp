#include "tread_wear/planning/trajectory_cost.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

std::string sampleError(std::size_t index, const char* field, double value, const std::string& constraint) {
  return "sample " + std::to_string(index) + ": " + field + " = " + valueText(value) + ": must be " + constraint;
}

/// FNV-1a over the bit patterns of doubles (-0 folded into 0 and every NaN into one, so equal values hash equal).
class Fnv1a {
 public:
  void add(double v) {
    if (v == 0.0) v = 0.0;
    if (std::isnan(v)) v = std::numeric_limits<double>::quiet_NaN();
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int i = 0; i < 8; ++i) {
      hash_ ^= (bits >> (8 * i)) & 0xffu;
      hash_ *= 0x100000001b3ull;
    }
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

VehicleWearSetup::VehicleWearSetup() { tread_temperature_c.fill(std::numeric_limits<double>::quiet_NaN()); }

bool VehicleWearSetup::validate(std::string* error) const {
  std::string inner;
  if (!vehicle.validate(&inner)) {
    if (error != nullptr) *error = "vehicle." + inner;
    return false;
  }
  for (int i = 0; i < kWheelCount; ++i) {
    const std::string prefix = std::string("tires[") + wheelName(i) + "].";
    if (!tires[static_cast<std::size_t>(i)].validate(&inner)) {
      if (error != nullptr) *error = prefix + inner;
      return false;
    }
    const double t = tread_temperature_c[static_cast<std::size_t>(i)];
    if (std::isinf(t))
      return failValidation(error, std::string("tread_temperature_c[") + wheelName(i) + "]", t,
                            "finite [degC], or NaN for unknown");
  }
  if (!model.validate(&inner)) {
    if (error != nullptr) *error = "model." + inner;
    return false;
  }
  if (model.time_budget_s != 0.0)
    return failValidation(error, "model.time_budget_s", model.time_budget_s,
                          "0 (a planner's cost uses the wanted preset, never a budget's coarser one)");
  if (!limits.validate(&inner)) {
    if (error != nullptr) *error = "limits." + inner;
    return false;
  }
  if (!(std::isfinite(max_path_curvature_per_m) && max_path_curvature_per_m > 0.0))
    return failValidation(error, "max_path_curvature_per_m", max_path_curvature_per_m, "finite and > 0 [1/m]");
  if (!(max_abs_grade_rad > 0.0 && max_abs_grade_rad < 1.5707963267948966))
    return failValidation(error, "max_abs_grade_rad", max_abs_grade_rad, "in (0, pi/2) [rad]");
  return true;
}

double VehicleWearSetup::effectiveTemperature(int wheel) const {
  const std::size_t i = static_cast<std::size_t>(wheel);
  const double t = tread_temperature_c[i];
  return tires[i].wear.temperature_enabled && std::isfinite(t) ? t : std::numeric_limits<double>::quiet_NaN();
}

std::uint64_t setupFingerprint(const VehicleWearSetup& s) {
  Fnv1a h;
  const VehicleParams& v = s.vehicle;
  for (double x : {v.mass_kg, v.wheelbase_m, v.cog_to_front_axle_m, v.cog_height_m, v.track_front_m,
                   v.track_rear_m, v.front_roll_stiffness_share, static_cast<double>(v.drive_layout),
                   v.all_wheel_front_drive_share, v.brake_balance_front, v.drag_coefficient, v.frontal_area_m2,
                   v.air_density_kg_per_m3, v.rolling_resistance_coefficient, v.cornering_stiffness_front_per_rad,
                   v.cornering_stiffness_rear_per_rad, v.longitudinal_slip_stiffness, v.gravity_mps2})
    h.add(x);
  for (int i = 0; i < kWheelCount; ++i) {
    const TireParams& t = s.tires[static_cast<std::size_t>(i)];
    const FootprintParams& f = t.footprint;
    const FrictionParams& r = t.friction;
    const TreadParams& d = t.tread;
    const WearLawParams& w = t.wear;
    for (double x : {f.a1_m, f.a2, f.a3_m, f.b_m, f.n_x, f.lambda_x, f.x_e_m, f.n_y, f.lambda_y, f.y_e_m, r.mu_0,
                     r.mu_m, r.v_m_mps, r.h, r.p_0_pa, r.p_ref_pa, r.q, d.k_y0_pa_per_m, d.k_y1_pa_per_m_n, d.phi,
                     d.c_x_pa_s_per_m, d.c_y_pa_s_per_m, d.m_kg_per_m2, w.w1, w.w2, w.w3_kg_per_s_m2,
                     w.w4_kg_per_s_m2, w.temperature_enabled ? 1.0 : 0.0, w.t0_c, w.sigma_t_c,
                     s.effectiveTemperature(i)})
      h.add(x);
  }
  const WearModelOptions& m = s.model;
  for (double x : {static_cast<double>(m.preset), static_cast<double>(m.orientation), m.min_speed_mps,
                   m.min_rolling_speed_mps, s.max_path_curvature_per_m})
    h.add(x);
  return h.value();
}

std::string fingerprintText(std::uint64_t fingerprint) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(fingerprint));
  return buffer;
}

std::array<std::string, kWheelCount> defaultVehicleWheelNames() {
  std::array<std::string, kWheelCount> names;
  for (int i = 0; i < kWheelCount; ++i) names[static_cast<std::size_t>(i)] = wheelName(i);
  return names;
}

bool matchVehicleWheels(const std::vector<std::string>& wheel_names,
                        const std::array<std::string, kWheelCount>& vehicle_wheel_names,
                        std::array<std::size_t, kWheelCount>* index_of_vehicle_wheel, std::string* error) {
  std::string listed;
  for (const std::string& n : wheel_names) listed += (listed.empty() ? "" : ", ") + n;
  for (std::size_t i = 0; i < kWheelCount; ++i) {
    std::size_t found = wheel_names.size();
    for (std::size_t k = 0; k < wheel_names.size(); ++k) {
      if (wheel_names[k] != vehicle_wheel_names[i]) continue;
      if (found != wheel_names.size()) {
        if (error != nullptr) *error = "wheel '" + wheel_names[k] + "' is named twice among [" + listed + "]";
        return false;
      }
      found = k;
    }
    if (found == wheel_names.size()) {
      if (error != nullptr)
        *error = "the wheels [" + listed + "] are not a four-wheel car: none is the " + wheelName(static_cast<int>(i)) +
                 " wheel '" + vehicle_wheel_names[i] + "'";
      return false;
    }
    (*index_of_vehicle_wheel)[i] = found;
  }
  return true;
}

const char* costStatusName(CostStatus status) {
  switch (status) {
    case CostStatus::kOk: return "ok";
    case CostStatus::kBadInput: return "bad_input";
    case CostStatus::kOutsideMap: return "outside_map";
    case CostStatus::kModelDomain: return "model_domain";
  }
  return "unknown";
}

bool checkSample(const VehicleWearSetup& setup, const TrajectorySample& s, std::size_t index, std::string* error) {
  const auto fail = [&](const char* field, double value, const std::string& constraint) {
    if (error != nullptr) *error = sampleError(index, field, value, constraint);
    return false;
  };
  if (!std::isfinite(s.time_s)) return fail("time_s", s.time_s, "finite [s]");
  if (!std::isfinite(s.speed_mps)) return fail("speed_mps", s.speed_mps, "finite [m/s]");
  if (s.speed_mps < 0.0) return fail("speed_mps", s.speed_mps, ">= 0 [m/s]");
  if (s.speed_mps > setup.limits.max_speed_mps)
    return fail("speed_mps", s.speed_mps, "<= limits.max_speed_mps = " + valueText(setup.limits.max_speed_mps) + " [m/s]");
  if (!std::isfinite(s.accel_mps2)) return fail("accel_mps2", s.accel_mps2, "finite [m/s^2]");
  if (!std::isfinite(s.path_curvature_per_m)) return fail("path_curvature_per_m", s.path_curvature_per_m, "finite [1/m]");
  if (std::fabs(s.path_curvature_per_m) > setup.max_path_curvature_per_m)
    return fail("path_curvature_per_m", s.path_curvature_per_m,
                "within +-max_path_curvature_per_m = " + valueText(setup.max_path_curvature_per_m) + " [1/m]");
  if (!std::isfinite(s.grade_rad)) return fail("grade_rad", s.grade_rad, "finite [rad]");
  if (std::fabs(s.grade_rad) > setup.max_abs_grade_rad)
    return fail("grade_rad", s.grade_rad,
                "within +-max_abs_grade_rad = " + valueText(setup.max_abs_grade_rad) + " [rad]");
  return true;
}

TrajectoryCost integrateTrajectory(const VehicleWearSetup& setup, const WheelRateSource& source,
                                   const TrajectorySample* samples, std::size_t n) {
  TrajectoryCost cost;
  if (n == 0 || samples == nullptr) {
    cost.status = CostStatus::kBadInput;
    cost.message = "empty trajectory: at least one sample is needed";
    return cost;
  }
  // Every sample is checked before any is evaluated: a bad last sample costs no model evaluations.
  for (std::size_t k = 0; k < n; ++k) {
    if (!checkSample(setup, samples[k], k, &cost.message)) {
      cost.status = CostStatus::kBadInput;
      cost.bad_sample = k;
      return cost;
    }
    if (k > 0 && !(samples[k].time_s > samples[k - 1].time_s)) {
      cost.status = CostStatus::kBadInput;
      cost.bad_sample = k;
      cost.message = sampleError(k, "time_s", samples[k].time_s,
                                 "> time_s of sample " + std::to_string(k - 1) + " = " + valueText(samples[k - 1].time_s) +
                                     " [s] (strictly increasing)");
      return cost;
    }
  }
  WheelRates previous, current;
  std::array<double, kWheelCount> stick_time{};  // integral of the stick fraction over time [s]
  for (std::size_t k = 0; k < n; ++k) {
    if (!source.rates(samples[k], &current, &cost.message)) {
      cost.status = source.failureStatus();
      cost.bad_sample = k;
      cost.message = "sample " + std::to_string(k) + ": " + cost.message;
      return cost;
    }
    if (k > 0) {
      const double dt = samples[k].time_s - samples[k - 1].time_s;
      cost.distance_m += 0.5 * (samples[k - 1].speed_mps + samples[k].speed_mps) * dt;
      for (std::size_t i = 0; i < kWheelCount; ++i) {
        cost.wheel_wear_kg[i] += 0.5 * (previous.wear_kg_per_s[i] + current.wear_kg_per_s[i]) * dt;
        stick_time[i] += 0.5 * (previous.stick_fraction[i] + current.stick_fraction[i]) * dt;
      }
    }
    previous = current;
  }
  cost.duration_s = samples[n - 1].time_s - samples[0].time_s;
  for (std::size_t i = 0; i < kWheelCount; ++i) {
    cost.total_wear_kg += cost.wheel_wear_kg[i];
    cost.stick_fraction[i] = n > 1 ? stick_time[i] / cost.duration_s : current.stick_fraction[i];
    cost.slide_fraction[i] = 1.0 - cost.stick_fraction[i];
  }
  cost.wear_per_distance_kg_per_m = cost.distance_m > 0.0 ? cost.total_wear_kg / cost.distance_m : 0.0;
  cost.status = CostStatus::kOk;
  cost.message.clear();
  return cost;
}

namespace {
/// The setup itself once validated, so that no member is built from an invalid one.
const VehicleWearSetup& validated(const VehicleWearSetup& setup) {
  std::string error;
  if (!setup.validate(&error)) throw std::invalid_argument("invalid vehicle wear setup: " + error);
  return setup;
}
}  // namespace

TrajectoryCostEvaluator::TrajectoryCostEvaluator(const VehicleWearSetup& setup)
    : setup_(validated(setup)), vehicle_(setup.vehicle) {
  for (std::size_t i = 0; i < kWheelCount; ++i) models_[i] = std::make_unique<WearModel>(setup_.tires[i], setup_.model);
}

void TrajectoryCostEvaluator::setPreset(Preset preset) {
  setup_.model.preset = preset;
  for (auto& m : models_) m->setPreset(preset);
}

void TrajectoryCostEvaluator::setTemperature(int wheel, double tread_temperature_c) {
  setup_.tread_temperature_c[static_cast<std::size_t>(wheel)] = tread_temperature_c;
}

void TrajectoryCostEvaluator::wheelStates(const TrajectorySample& sample, VehicleState* state) const {
  vehicle_.evaluate({sample.speed_mps, sample.accel_mps2, sample.path_curvature_per_m, sample.grade_rad}, state);
}

bool TrajectoryCostEvaluator::rates(const TrajectorySample& sample, WheelRates* rates, std::string* error) const {
  VehicleState state;
  wheelStates(sample, &state);
  // The stamp of every input is the sample's time, so the temperature is fresh for evaluateInputs().
  constexpr double kFreshness_s = 1.0;
  const double t = sample.time_s;
  for (int i = 0; i < kWheelCount; ++i) {
    const std::size_t w = static_cast<std::size_t>(i);
    const WheelState& s = state.wheels[w];
    WheelInputs inputs(setup_.limits);
    const double temperature = setup_.effectiveTemperature(i);
    const std::pair<InputKind, InputFault> checks[] = {
        {InputKind::kLoad, inputs.setLoad(t, s.load_n)},
        {InputKind::kSpeed, inputs.setSpeed(t, s.speed_mps)},
        {InputKind::kSlip, inputs.setSlip(t, s.slip_angle_rad, s.slip_ratio, s.path_curvature_per_m)},
        {InputKind::kTemperature,
         std::isnan(temperature) ? InputFault::kNone : inputs.setTemperature(t, temperature)}};
    for (const auto& [kind, fault] : checks) {
      if (fault == InputFault::kNone) continue;
      if (error != nullptr) {
        std::ostringstream msg;
        msg.precision(10);
        msg << "wheel " << wheelName(i) << ": " << inputKindName(kind) << " input rejected (" << inputFaultName(fault)
            << "; load_n = " << s.load_n << ", slip_angle_rad = " << s.slip_angle_rad
            << ", slip_ratio = " << s.slip_ratio << ", path_curvature_per_m = " << s.path_curvature_per_m
            << ", speed_mps = " << s.speed_mps << ")";
        *error = msg.str();
      }
      return false;
    }
    WearResult result;
    if (evaluateInputs(*models_[w], inputs, t, kFreshness_s, &result) == EvalStatus::kInvalidInput) {
      if (error != nullptr)
        *error = std::string("wheel ") + wheelName(i) + ": operating point outside the wear model's domain";
      return false;
    }
    rates->wear_kg_per_s[w] = result.wear_rate_kg_per_s;
    rates->stick_fraction[w] = result.stick_fraction;
  }
  return true;
}

}  // namespace tread_wear
