#pragma once
/// @file operating_point.h
/// Operating conditions of one wheel and their kinematics (model spec, "Kinematics").
///
/// Axes: ISO 8855 tire axes at the contact centre: x forward (leading edge at x = +a), y left, z up.
/// Forces and moments are those the road applies to the tire.
///   alpha  slip angle: tan(alpha) = V_y / V_x, positive when the wheel centre moves to the left of its
///          heading; a positive alpha gives a negative side force (Fy = -C alpha near zero).
///   kappa  slip ratio (V_r - V_x)/V_x with V_x = V cos(alpha); positive when driving.
///   c      path curvature 1/R: positive when the wheel turns left (turn centre on +y), 0 when straight.
/// Relative velocity the tread tip at (x + delta_x, y + delta_y) must have to stick to the road
/// (the paper's Eq 14 generalised; Omega = V c is the yaw rate of the wheel over the road):
///   v_rx = kappa V_x + Omega (y + delta_y)
///   v_ry = -V sin(alpha) - Omega (x + delta_x)
/// The Grip and Abrasion Test Stand is the special case kappa = 0, |R| = R_t = 60 mm. Eq 14 read
/// literally (omega_z > 0, alpha > 0 in the paper's axes) is, mirrored into ISO axes, alpha < 0 with
/// R = +R_t: the side force points to the track centre. The other orientation is the option
/// TurnSlipOrientation::kFlipped. Fictitious forces of the yawing frame (order m Omega v) are neglected.

#include <cmath>
#include <limits>
#include <string>

namespace tread_wear {

/// Which way the slip angle is oriented against the track curve (model spec, "Kinematics": the paper does not
/// pin it down; the calibration decides with data).
enum class TurnSlipOrientation {
  kLiteral,  ///< path curvature used as given (Eq 14 read literally for the rig tables)
  kFlipped   ///< path curvature negated: slip angle oriented the other way against the track curve
};

/// The road's velocity relative to the wheel under the tread tip at (x + delta_x, y + delta_y) (Eq 14 generalised,
/// see above), split into the slip terms and the yaw rate:
///   v_rx = v_rx0 + Omega (y + delta_y),  v_ry = v_ry0 - Omega (x + delta_x)
/// The one implementation of these terms for the marcher and the reference solver.
struct TipKinematics {
  double omega_rad_per_s = 0.0;  ///< Omega = V/R, the wheel's yaw rate over the road, sign per orientation [rad/s]
  double v_rx0_mps = 0.0;        ///< kappa V_x [m/s]
  double v_ry0_mps = 0.0;        ///< -V sin(alpha) [m/s]

  /// v_rx [m/s] at the tip's lateral position y + delta_y [m].
  double vrx(double y_tip_m) const { return v_rx0_mps + omega_rad_per_s * y_tip_m; }
  /// v_ry [m/s] at the tip's longitudinal position x + delta_x [m].
  double vry(double x_tip_m) const { return v_ry0_mps - omega_rad_per_s * x_tip_m; }
};

struct OperatingPoint {
  double speed_mps = 0.0;             ///< V, speed of the wheel centre over the road [m/s], >= 0
  double slip_angle_rad = 0.0;        ///< alpha [rad], |alpha| < pi/2
  double slip_ratio = 0.0;            ///< kappa [-], > -1
  double path_curvature_per_m = 0.0;  ///< 1/R [1/m], ISO sign (left turn positive); 0 = straight
  double load_n = 0.0;                ///< vertical load Fz [N], > 0
  double tread_temperature_c = std::numeric_limits<double>::quiet_NaN();  ///< [degC]; NaN = unknown

  /// Names the first field that is non-finite or outside its physical range.
  bool validate(std::string* error) const;
  /// Longitudinal speed V_x = V cos(alpha) [m/s].
  double longitudinalSpeed() const { return speed_mps * std::cos(slip_angle_rad); }
  /// Rolling speed V_r = V_x (1 + kappa) [m/s]: the speed at which tread elements cross the patch.
  double rollingSpeed() const { return longitudinalSpeed() * (1.0 + slip_ratio); }
  /// Slip terms and yaw rate of v_r (Eq 14 generalised) with the path curvature oriented as `orientation` says.
  TipKinematics tipKinematics(TurnSlipOrientation orientation) const {
    const double curvature =
        orientation == TurnSlipOrientation::kFlipped ? -path_curvature_per_m : path_curvature_per_m;
    return {speed_mps * curvature, slip_ratio * longitudinalSpeed(), -speed_mps * std::sin(slip_angle_rad)};
  }
};

/// An operating point of a drive with its share of the drive's integrals (drive segments: estimation/drive_segments.h).
/// A quantity q integrated over the drive by the trapezoid rule is the sum of q(op) time_s over its points; wear
/// per time is W_r(op) times the wheel's own speed, so the wear is the sum of W_r(op) distance_m.
struct WeightedOperatingPoint {
  OperatingPoint op;        ///< the point the model is evaluated at (low-speed convention applied), T included
  double time_s = 0.0;      ///< time weight [s], >= 0
  double distance_m = 0.0;  ///< distance weight [m] = time weight times the wheel's speed, >= 0
};

}  // namespace tread_wear
