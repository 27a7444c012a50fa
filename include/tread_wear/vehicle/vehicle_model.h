#pragma once
/// @file vehicle_model.h
/// Quasi-steady four-wheel vehicle model: from the vehicle's speed, longitudinal acceleration and path
/// curvature to each wheel's load, slip angle, slip ratio, speed and path curvature (the node's inputs).
///
/// Model (rigid body on a straight grade theta, quasi-steady: no pitch/roll/yaw dynamics, no suspension kinematics):
///   lateral acceleration   a_y = v^2 kappa,  yaw rate r = v kappa  (kappa of the CoG path, > 0 left)
///   grade                  theta > 0 uphill: the weight's component m g sin(theta) along the road acts at the CoG
///                          like an inertial force, m g cos(theta) presses the wheels on the road (theta = 0: flat)
///   bank (crossfall)       phi > 0 when the road's left edge is lower. The path curvature is horizontal, so in the
///                          road plane the tires carry the specific side force a_y,road = a_y cos(phi) - g cos(theta)
///                          sin(phi) (a bank towards the inside of a turn relieves them) and the road presses with
///                          m (g cos(theta) cos(phi) + a_y sin(phi)); a_y,road sets the side forces and the lateral
///                          load transfer below (phi = 0: a_y,road = a_y exactly)
///   driving resistances    F_aero = rho/2 c_d A v^2,  F_roll = f_r N ramp(v) (N the road normal force, ramp = min(1,
///   v/0.5 m/s):
///                          no rolling resistance at standstill)
///   force demand           F = m a_x + F_aero + F_roll + m g sin(theta) (> 0 drive torque, < 0 brake torque)
///   axle loads             N l_r / L - dFz_x (front),  N l_f / L + dFz_x (rear)
///   longitudinal transfer  dFz_x = (m a_x + F_aero + m g sin(theta)) h / L  (drag and grade force at CoG height;
///                          front loses it)
///   lateral transfer       dFz_f = m a_y,road h lambda_f / t_f,  dFz_r = m a_y,road h (1 - lambda_f) / t_r
///                          (roll-stiffness share lambda_f, no roll-centre heights; outer wheels gain it)
///   axle side forces       Fy_f = m a_y,road l_r / L,  Fy_r = m a_y,road l_f / L  (steady-state single track)
///   axle slip angles       alpha_axle = -Fy_axle / (c_alpha Fz_axle)  (linear, cornering stiffness
///                          proportional to axle load; ISO sign: a left force needs alpha < 0)
///   wheel kinematics       rigid body turning about its instant centre: wheel velocity v_CoG + r x p_i,
///                          fixed by the rear-axle slip angle; rear slip angles from their velocities;
///                          wheel speed V_i = |v_i|; wheel path curvature r / V_i.
///   front steer angles     ideal angles delta_i,ideal = atan2(v_i,y, v_i,x) - alpha_f put each front wheel at the
///                          front-axle slip angle alpha_f; with Ackermann share A the geometry steers them to
///                          delta_i = delta + A (delta_i,ideal - delta), delta the mean of the ideal angles (the same
///                          form as vehicle_input_estimator.h), so alpha_i = alpha_f + (1 - A) (delta_i,ideal - delta):
///                          below A = 1 the two front tyres take opposite slip angles and scrub against each other,
///                          +-(1 - A) L t_f / (2 R^2) on a turn of radius R >> L, t_f at low speed
///   wheel longitudinal     Fx_i = share_i F - f_r Fz_i ramp(v)  (drive shares by layout, brake shares by
///                          balance, split equally left/right); slip ratio from the brush-type law
///                          Fx = C_kappa kappa/(1 + kappa) with C_kappa = c_kappa Fz_i, so kappa = u/(1 - u),
///                          u = Fx_i/(c_kappa Fz_i), saturated at |u| <= 0.5 (far beyond normal driving).
/// Symbols: m mass, g gravity, L wheelbase, l_f/l_r CoG to front/rear axle, h CoG height, t_f/t_r tracks.
/// Sign conventions: ISO 8855 (x forward, y left, z up), as operating_point.h.
/// Limits: no aerodynamic lift, no change of bank or grade along the wheelbase, no combined-slip coupling in the slip
/// estimates, no transient tire lag; slip estimates are linear, the brush model (WearModel) then gives the actual
/// forces.

#include <array>
#include <string>

namespace tread_wear {

enum class DriveLayout { kFront = 0, kRear = 1, kAll = 2 };
/// "front", "rear", "all".
const char* driveLayoutName(DriveLayout layout);
bool parseDriveLayout(const std::string& name, DriveLayout* layout);

struct VehicleParams {
  std::string name = "passenger_car";
  double mass_kg = 1450.0;                  ///< m, vehicle with driver [kg], > 0
  double wheelbase_m = 2.64;                ///< L [m], > 0
  double cog_to_front_axle_m = 1.06;        ///< l_f [m], in (0, L)
  double cog_height_m = 0.55;               ///< h [m], >= 0
  double track_front_m = 1.55;              ///< t_f [m], > 0
  double track_rear_m = 1.52;               ///< t_r [m], > 0
  double front_roll_stiffness_share = 0.6;  ///< lambda_f [-], in [0, 1]
  DriveLayout drive_layout = DriveLayout::kFront;
  double all_wheel_front_drive_share = 0.5;         ///< front share of drive torque when all-wheel driven [-], [0, 1]
  double brake_balance_front = 0.7;                 ///< front share of brake torque [-], in [0, 1]
  double ackermann_share = 1.0;  ///< A: 1 ideal Ackermann about the rear axle, 0 parallel steering [-], in [0, 1]
  double drag_coefficient = 0.30;                   ///< c_d [-], >= 0
  double frontal_area_m2 = 2.2;                     ///< A [m^2], >= 0
  double air_density_kg_per_m3 = 1.2;               ///< rho [kg/m^3], >= 0
  double rolling_resistance_coefficient = 0.010;    ///< f_r [-], >= 0
  double cornering_stiffness_front_per_rad = 12.6;  ///< c_alpha front: C_alpha/Fz [1/rad], > 0
  double cornering_stiffness_rear_per_rad = 12.6;   ///< c_alpha rear: C_alpha/Fz [1/rad], > 0
  double longitudinal_slip_stiffness = 16.4;        ///< c_kappa: C_kappa/Fz [-], > 0
  double gravity_mps2 = 9.81;                       ///< g [m/s^2], > 0

  bool validate(std::string* error) const;
  double cogToRearAxle_m() const { return wheelbase_m - cog_to_front_axle_m; }
};

/// Wheel order everywhere: front left, front right, rear left, rear right.
constexpr int kWheelCount = 4;
enum WheelIndex { kFrontLeft = 0, kFrontRight = 1, kRearLeft = 2, kRearRight = 3 };
/// "front_left", "front_right", "rear_left", "rear_right" (the wheel names of config/vehicle_wheels.yaml).
const char* wheelName(int wheel);

/// Motion of the vehicle at one instant.
struct VehicleMotion {
  double speed_mps = 0.0;             ///< v, CoG speed [m/s], >= 0
  double accel_mps2 = 0.0;            ///< a_x = dv/dt [m/s^2]
  double path_curvature_per_m = 0.0;  ///< kappa of the CoG path [1/m], > 0 left
  double grade_rad = 0.0;             ///< theta, road grade [rad], > 0 uphill, |theta| < pi/2 (0: flat road)
  double bank_rad = 0.0;              ///< phi, road bank [rad], > 0 left edge lower, |phi| < pi/2 (0: level)
};

/// One wheel's inputs for the wear model, plus the force demands they were derived from.
struct WheelState {
  double load_n = 0.0;                ///< Fz [N], >= 0
  double slip_angle_rad = 0.0;        ///< alpha [rad], ISO
  double slip_ratio = 0.0;            ///< kappa [-], > 0 driving
  double path_curvature_per_m = 0.0;  ///< wheel path curvature [1/m], > 0 left
  double speed_mps = 0.0;             ///< wheel centre speed over the road [m/s]
  double fx_demand_n = 0.0;           ///< longitudinal force the slip ratio was set for [N]
  double fy_demand_n = 0.0;           ///< lateral force share of the wheel's axle at the linear estimate [N]
};

struct VehicleState {
  std::array<WheelState, kWheelCount> wheels;
  double lateral_accel_mps2 = 0.0;  ///< a_y [m/s^2]
  double force_demand_n = 0.0;      ///< F = m a_x + F_aero + F_roll + m g sin(theta) [N]
  double sideslip_rad = 0.0;        ///< beta, CoG velocity direction relative to the body [rad]
  double steer_angle_rad = 0.0;     ///< mean front steer angle [rad]
};

class VehicleModel {
 public:
  /// @throw std::invalid_argument naming the field for invalid params
  explicit VehicleModel(const VehicleParams& params);
  /// Evaluates the quasi-steady state. Allocates nothing.
  void evaluate(const VehicleMotion& motion, VehicleState* state) const;
  /// Static load of each wheel [N].
  double staticLoad(int wheel) const;
  const VehicleParams& params() const { return params_; }

 private:
  VehicleParams params_;
};

}  // namespace tread_wear
