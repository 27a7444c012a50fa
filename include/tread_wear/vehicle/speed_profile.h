#pragma once
/// @file speed_profile.h
/// A vehicle speed profile over time (a driving cycle such as WLTC class 3b), read from CSV and
/// interpolated smoothly so that the longitudinal acceleration is continuous. Files are read by
/// io/speed_profile_csv.h.
///
/// CSV format: lines starting with '#' are comments; the first other line is the header; columns
/// `time_s` and either `speed_kmh` or `speed_mps` are required (others ignored). Times strictly
/// increasing, speeds finite and >= 0. Phases (optional) come from one comment line of the form
///   # Phases: Low 0-589, Medium 590-1022, High 1023-1477, Extra High 1478-1800.
/// (name, start second, end second, ending at ". " or the line end; the form the UN GTR 15 tables and
/// data/wltc_class3b.csv use). A phase [start, end] covers the times start <= t < next phase start (the last one up to
/// its end).
///
/// Interpolation: monotone piecewise cubic Hermite (Fritsch-Carlson, "PCHIP"). Between two samples the
/// speed stays within their range (no overshoot, never negative), and the acceleration dv/dt is continuous
/// at the samples, unlike linear interpolation whose acceleration jumps at every sample of a 1 Hz cycle.
/// Distance is the exact integral of the cubic.

#include <string>
#include <vector>

namespace tread_wear {

/// A named part of a cycle (WLTC: Low, Medium, High, Extra High).
struct ProfilePhase {
  std::string name;
  double start_s = 0.0;  ///< first time of the phase [s]
  double end_s = 0.0;    ///< last time of the phase [s]
};

class SpeedProfile {
 public:
  /// @param time_s sample times [s], strictly increasing, at least 2
  /// @param speed_mps sample speeds [m/s], finite and >= 0
  /// @throw std::invalid_argument naming the first bad sample
  SpeedProfile(std::vector<double> time_s, std::vector<double> speed_mps,
               std::vector<ProfilePhase> phases = {}, std::string name = "");

  double startTime_s() const { return t_.front(); }
  double endTime_s() const { return t_.back(); }
  double duration_s() const { return t_.back() - t_.front(); }
  /// Speed v(t) [m/s]; clamped to the end values outside the profile.
  double speed(double t_s) const;
  /// Acceleration dv/dt [m/s^2]; 0 outside the profile.
  double acceleration(double t_s) const;
  /// Distance travelled from the start to t [m].
  double distance(double t_s) const;
  double totalDistance_m() const { return cumulative_m_.back(); }
  double maxSpeed_mps() const;
  /// Largest speed over [t0, t1] [m/s] (exact: the interpolant does not overshoot its samples).
  double maxSpeed(double t0_s, double t1_s) const;
  /// Index of the phase containing t, or -1 when there are no phases or t is outside them.
  int phaseAt(double t_s) const;

  const std::vector<double>& times_s() const { return t_; }
  const std::vector<double>& speeds_mps() const { return v_; }
  const std::vector<ProfilePhase>& phases() const { return phases_; }
  const std::string& name() const { return name_; }

 private:
  std::size_t interval(double t_s) const;
  std::vector<double> t_, v_, slope_, cumulative_m_;
  std::vector<ProfilePhase> phases_;
  std::string name_;
};

/// Index of the phase containing t (phase i covers [start_i, start_{i+1}), the last [start, end]), or -1.
int phaseIndexAt(const std::vector<ProfilePhase>& phases, double t_s);

}  // namespace tread_wear
