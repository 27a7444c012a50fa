#include "tread_wear/vehicle/vehicle_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {

namespace {

bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool nonNegative(double v) { return std::isfinite(v) && v >= 0.0; }
bool unitInterval(double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; }

/// Rolling resistance builds up over the first half metre per second: none at standstill [m/s].
constexpr double kRollingRampSpeed_mps = 0.5;
/// Saturation of the linear slip-ratio estimate |Fx / C_kappa| (kappa = 1 driving, -1/3 braking) [-].
constexpr double kMaxSlipUtilisation = 0.5;

}  // namespace

const char* driveLayoutName(DriveLayout layout) {
  switch (layout) {
    case DriveLayout::kFront:
      return "front";
    case DriveLayout::kRear:
      return "rear";
    case DriveLayout::kAll:
      return "all";
  }
  return "unknown";
}

bool parseDriveLayout(const std::string& name, DriveLayout* layout) {
  for (DriveLayout l : {DriveLayout::kFront, DriveLayout::kRear, DriveLayout::kAll}) {
    if (name == driveLayoutName(l)) {
      *layout = l;
      return true;
    }
  }
  return false;
}

const char* wheelName(int wheel) {
  static const char* const kNames[kWheelCount] = {"front_left", "front_right", "rear_left", "rear_right"};
  return wheel >= 0 && wheel < kWheelCount ? kNames[wheel] : "unknown";
}

bool VehicleParams::validate(std::string* error) const {
  if (!positive(mass_kg)) return failValidation(error, "mass_kg", mass_kg, "finite and > 0");
  if (!positive(wheelbase_m)) return failValidation(error, "wheelbase_m", wheelbase_m, "finite and > 0");
  if (!positive(cog_to_front_axle_m) || !(cog_to_front_axle_m < wheelbase_m))
    return failValidation(error, "cog_to_front_axle_m", cog_to_front_axle_m, "in (0, wheelbase_m)");
  if (!nonNegative(cog_height_m)) return failValidation(error, "cog_height_m", cog_height_m, "finite and >= 0");
  if (!positive(track_front_m)) return failValidation(error, "track_front_m", track_front_m, "finite and > 0");
  if (!positive(track_rear_m)) return failValidation(error, "track_rear_m", track_rear_m, "finite and > 0");
  if (!unitInterval(front_roll_stiffness_share))
    return failValidation(error, "front_roll_stiffness_share", front_roll_stiffness_share, "in [0, 1]");
  if (!unitInterval(all_wheel_front_drive_share))
    return failValidation(error, "all_wheel_front_drive_share", all_wheel_front_drive_share, "in [0, 1]");
  if (!unitInterval(brake_balance_front))
    return failValidation(error, "brake_balance_front", brake_balance_front, "in [0, 1]");
  if (!unitInterval(ackermann_share)) return failValidation(error, "ackermann_share", ackermann_share, "in [0, 1]");
  if (!nonNegative(drag_coefficient))
    return failValidation(error, "drag_coefficient", drag_coefficient, "finite and >= 0");
  if (!nonNegative(frontal_area_m2))
    return failValidation(error, "frontal_area_m2", frontal_area_m2, "finite and >= 0");
  if (!nonNegative(air_density_kg_per_m3))
    return failValidation(error, "air_density_kg_per_m3", air_density_kg_per_m3, "finite and >= 0");
  if (!nonNegative(rolling_resistance_coefficient))
    return failValidation(error, "rolling_resistance_coefficient", rolling_resistance_coefficient, "finite and >= 0");
  if (!positive(cornering_stiffness_front_per_rad))
    return failValidation(error, "cornering_stiffness_front_per_rad", cornering_stiffness_front_per_rad,
                          "finite and > 0");
  if (!positive(cornering_stiffness_rear_per_rad))
    return failValidation(error, "cornering_stiffness_rear_per_rad", cornering_stiffness_rear_per_rad,
                          "finite and > 0");
  if (!positive(longitudinal_slip_stiffness))
    return failValidation(error, "longitudinal_slip_stiffness", longitudinal_slip_stiffness, "finite and > 0");
  if (!positive(gravity_mps2)) return failValidation(error, "gravity_mps2", gravity_mps2, "finite and > 0");
  return true;
}

VehicleModel::VehicleModel(const VehicleParams& params) : params_(params) {
  std::string error;
  if (!params_.validate(&error)) throw std::invalid_argument("invalid vehicle parameters: " + error);
}

double VehicleModel::staticLoad(int wheel) const {
  const VehicleParams& p = params_;
  const double axle_share =
      wheel < kRearLeft ? p.cogToRearAxle_m() / p.wheelbase_m : p.cog_to_front_axle_m / p.wheelbase_m;
  return 0.5 * p.mass_kg * p.gravity_mps2 * axle_share;
}

void VehicleModel::evaluate(const VehicleMotion& motion, VehicleState* state) const {
  const VehicleParams& p = params_;
  const double m = p.mass_kg, g = p.gravity_mps2, L = p.wheelbase_m, h = p.cog_height_m;
  const double l_f = p.cog_to_front_axle_m, l_r = p.cogToRearAxle_m();
  const double v = std::max(motion.speed_mps, 0.0);
  const double kappa = motion.path_curvature_per_m;
  const double a_y = v * v * kappa;
  const double rolling_ramp = std::min(1.0, v / kRollingRampSpeed_mps);
  // Weight normal to and along the road (grade 0, bank 0: m g and 0 exactly, so the flat-road results are unchanged).
  const double cos_bank = std::cos(motion.bank_rad), sin_bank = std::sin(motion.bank_rad);
  const double normal_weight = m * g * std::cos(motion.grade_rad) * cos_bank + m * a_y * sin_bank;
  const double grade_force = m * g * std::sin(motion.grade_rad);
  // Specific side force the tires carry in the road plane: a bank towards the inside of the turn relieves them.
  const double a_y_road = a_y * cos_bank - g * std::cos(motion.grade_rad) * sin_bank;

  const double f_aero = 0.5 * p.air_density_kg_per_m3 * p.drag_coefficient * p.frontal_area_m2 * v * v;
  const double f_roll = p.rolling_resistance_coefficient * normal_weight * rolling_ramp;
  const double demand = m * motion.accel_mps2 + f_aero + f_roll + grade_force;
  state->lateral_accel_mps2 = a_y;
  state->force_demand_n = demand;

  // Loads: static + longitudinal transfer per axle, then lateral transfer within each axle.
  const double dfz_long = (m * motion.accel_mps2 + f_aero + grade_force) * h / L;
  const double fz_front = normal_weight * l_r / L - dfz_long;
  const double fz_rear = normal_weight * l_f / L + dfz_long;
  const double dfz_front = m * a_y_road * h * p.front_roll_stiffness_share / p.track_front_m;
  const double dfz_rear = m * a_y_road * h * (1.0 - p.front_roll_stiffness_share) / p.track_rear_m;
  std::array<double, kWheelCount> fz = {0.5 * fz_front - dfz_front, 0.5 * fz_front + dfz_front,
                                        0.5 * fz_rear - dfz_rear, 0.5 * fz_rear + dfz_rear};
  for (double& load : fz) load = std::max(load, 0.0);

  // Steady-state single track: axle side forces and linear axle slip angles.
  const double fy_front = m * a_y_road * l_r / L, fy_rear = m * a_y_road * l_f / L;
  const double axle_front = fz[kFrontLeft] + fz[kFrontRight], axle_rear = fz[kRearLeft] + fz[kRearRight];
  const double alpha_front = axle_front > 0.0 ? -fy_front / (p.cornering_stiffness_front_per_rad * axle_front) : 0.0;
  const double alpha_rear = axle_rear > 0.0 ? -fy_rear / (p.cornering_stiffness_rear_per_rad * axle_rear) : 0.0;

  // Rigid-body kinematics in units of v: rear-axle centre velocity u (cos, sin)(alpha_rear); the CoG is
  // l_r ahead, so v_CoG/v = (u cos alpha_r, u sin alpha_r + kappa l_r) with |v_CoG/v| = 1.
  const double ca = std::cos(alpha_rear), sa = std::sin(alpha_rear);
  const double disc = std::max(0.0, 1.0 - kappa * kappa * l_r * l_r * ca * ca);
  const double u = -sa * kappa * l_r + std::sqrt(disc);
  state->sideslip_rad = std::atan2(u * sa + kappa * l_r, u * ca);
  const std::array<double, kWheelCount> x = {l_f, l_f, -l_r, -l_r};
  const std::array<double, kWheelCount> y = {0.5 * p.track_front_m, -0.5 * p.track_front_m, 0.5 * p.track_rear_m,
                                             -0.5 * p.track_rear_m};

  // Longitudinal shares of the force demand: drive torque by layout, brake torque by balance.
  double front_share = p.brake_balance_front;
  if (demand > 0.0) {
    front_share = p.drive_layout == DriveLayout::kFront  ? 1.0
                  : p.drive_layout == DriveLayout::kRear ? 0.0
                                                         : p.all_wheel_front_drive_share;
  }

  std::array<double, kWheelCount> heading{}, speed_ratio{};  // of each wheel's velocity, in units of v
  for (int i = 0; i < kWheelCount; ++i) {
    const double wx = u * ca - kappa * y[i], wy = u * sa + kappa * (l_r + x[i]);
    heading[i] = std::atan2(wy, wx);
    speed_ratio[i] = std::hypot(wx, wy);
  }
  const double mean_steer = 0.5 * ((heading[kFrontLeft] - alpha_front) + (heading[kFrontRight] - alpha_front));
  for (int i = 0; i < kWheelCount; ++i) {
    WheelState& w = state->wheels[static_cast<std::size_t>(i)];
    const bool front = i < kRearLeft;
    w.load_n = fz[i];
    w.speed_mps = v * speed_ratio[i];
    w.path_curvature_per_m = speed_ratio[i] > 0.0 ? kappa / speed_ratio[i] : 0.0;
    if (!front)
      w.slip_angle_rad = heading[i];
    else if (p.ackermann_share < 1.0)
      w.slip_angle_rad = alpha_front + (1.0 - p.ackermann_share) * (heading[i] - alpha_front - mean_steer);
    else
      w.slip_angle_rad = alpha_front;  // ideal: the axle's angle as it is (a signed zero on the straight stays one)
    const double axle_load = front ? axle_front : axle_rear;
    w.fy_demand_n = axle_load > 0.0 ? (front ? fy_front : fy_rear) * fz[i] / axle_load : 0.0;
    const double share = 0.5 * (front ? front_share : 1.0 - front_share);
    w.fx_demand_n = share * demand - p.rolling_resistance_coefficient * fz[i] * rolling_ramp;
    if (fz[i] > 0.0) {
      const double utilisation = std::clamp(w.fx_demand_n / (p.longitudinal_slip_stiffness * fz[i]),
                                            -kMaxSlipUtilisation, kMaxSlipUtilisation);
      w.slip_ratio = utilisation / (1.0 - utilisation);
    } else {
      w.slip_ratio = 0.0;
    }
  }
  state->steer_angle_rad = mean_steer;
}

}  // namespace tread_wear
