#pragma once
/// @file trajectory_cost.h
/// A planner's wear cost at the vehicle level (issue 24, part 3), free of ROS: candidate trajectories of the
/// vehicle -> per-wheel loads and slips (quasi-steady VehicleModel) -> per-wheel wear rate (WearModel, the live
/// tires' parameters, preset and tread temperature) -> wear per wheel and in total [kg], per distance [kg/m] and
/// the time-weighted stick/slide fractions. The map (wear_map.h) evaluates the same cost from a precomputed grid.
///
/// Per sample k (time t_k, CoG speed v_k, longitudinal acceleration a_x,k, CoG path curvature kappa_k, optional
/// road grade theta_k):
///   VehicleModel::evaluate({v, a_x, kappa, theta})  -> per wheel load, slip angle, slip ratio, path curvature, speed
///   the wheel state goes through WheelInputs (the live topics' validation, InputLimits) and evaluateInputs()
///   (the one place that builds the model's operating point; zero load wears nothing) -> wdot_i [kg/s]
/// Integration (trapezoid rule over the samples' own times, as WheelEstimator integrates live):
///   wear_i   = sum_k 0.5 (wdot_i,k + wdot_i,k+1) (t_k+1 - t_k)            [kg]
///   distance = sum_k 0.5 (v_k + v_k+1) (t_k+1 - t_k)                      [m], CoG path length
///   stick_i  = sum_k 0.5 (s_i,k + s_i,k+1) dt_k / duration                [-], time-weighted mean of the area
///              fraction of the patch with |v_s| <= v_m (paper Section 4); slide_i = 1 - stick_i. Time-weighted
///              (not wear-weighted) so that it reads as "how much of the time the patch is in stick". A single
///              sample (duration 0) reports its own fractions and wears nothing.
///   total    = sum_i wear_i;   wear per distance = total / distance [kg/m] (0 for a trajectory that does not move)
/// The samples are taken as given: a_x need not be dv/dt of the samples (a planner's profile may not be exact).
///
/// Assumptions and limits (those of VehicleModel, vehicle_model.h): a straight grade under the car (no banking),
/// quasi-steady (no transient tire lag, no pitch/roll dynamics), linear slip estimates. The map (wear_map.h) is for
/// a flat road only.
/// |kappa| is bounded by VehicleWearSetup::max_path_curvature_per_m (a road car's tightest turn): the
/// kinematics of the quasi-steady model leave their domain for turns tighter than the wheelbase allows.
///
/// Errors: bad input gets a status and a message naming the trajectory's sample index, the field, its value and
/// the broken constraint (NaN, negative speed, non-increasing time, empty trajectory, curvature beyond the bound).
/// Never throws for bad samples; only constructors throw for invalid setups.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/wear_model.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {

/// One sample of a candidate trajectory of the vehicle.
struct TrajectorySample {
  double time_s = 0.0;                ///< t [s], strictly increasing along a trajectory
  double speed_mps = 0.0;             ///< v, CoG speed [m/s], >= 0
  double accel_mps2 = 0.0;            ///< a_x, longitudinal acceleration [m/s^2]
  double path_curvature_per_m = 0.0;  ///< kappa of the CoG path [1/m], > 0 left (ISO 8855)
  double grade_rad = 0.0;             ///< theta, road grade [rad], > 0 uphill (0: flat road)
};

/// What a cost is evaluated for: the vehicle, the four tires (vehicle wheel order, vehicle_model.h) and how the
/// wear model runs. The node fills it from its live wheels; the tool from files.
struct VehicleWearSetup {
  VehicleParams vehicle;
  std::array<TireParams, kWheelCount> tires;
  /// Tread temperature per wheel [degC]; NaN = unknown (Eq 25 off for that wheel; it is off anyway when the tire's
  /// wear law has temperature_enabled = false).
  std::array<double, kWheelCount> tread_temperature_c;
  WearModelOptions model;   ///< preset, orientation, low-speed thresholds; time_budget_s must be 0 (planner: exact)
  InputLimits limits;       ///< plausibility limits the wheel states pass, as the live topics do
  double max_path_curvature_per_m = 0.25;  ///< |kappa| bound of a sample [1/m], > 0 (0.25: 4 m radius, tighter
                                           ///< than a passenger car's ~5 m turning circle)
  double max_abs_grade_rad = 0.35;  ///< |theta| bound of a sample [rad], in (0, pi/2) (0.35: 36 %, steeper than
                                    ///< public roads)

  VehicleWearSetup();
  /// false with *error "<field> = <value>: must be <constraint>" for the first broken constraint.
  bool validate(std::string* error) const;
  /// Temperature the model actually sees for a wheel: NaN when unknown or when its tire ignores temperature.
  double effectiveTemperature(int wheel) const;
};

/// 64-bit FNV-1a over every number of the setup that changes a cost (vehicle, tires, effective temperatures,
/// model options, curvature bound; not the names). Equal setups give equal fingerprints.
std::uint64_t setupFingerprint(const VehicleWearSetup& setup);
/// The fingerprint as 16 hex digits.
std::string fingerprintText(std::uint64_t fingerprint);

/// Which of `wheel_names` (a node's or a wheel file's wheels) is each vehicle wheel: vehicle_wheel_names[i] names
/// vehicle wheel i (front_left, front_right, rear_left, rear_right: wheelName(i) when that is how the wheels are
/// named). false with *error saying why the wheels are not a four-wheel car (a vehicle wheel that none of them is,
/// or a name given twice); *index_of_vehicle_wheel[i] = index into wheel_names.
bool matchVehicleWheels(const std::vector<std::string>& wheel_names,
                        const std::array<std::string, kWheelCount>& vehicle_wheel_names,
                        std::array<std::size_t, kWheelCount>* index_of_vehicle_wheel, std::string* error);
/// The default vehicle wheel names: front_left, front_right, rear_left, rear_right (config/vehicle_wheels.yaml).
std::array<std::string, kWheelCount> defaultVehicleWheelNames();

enum class CostStatus : std::uint8_t {
  kOk = 0,
  kBadInput = 1,     ///< a sample failed validation (message names it), or the trajectory is empty
  kOutsideMap = 2,   ///< map evaluation: a sample lies outside the map's axes (message names the axis)
  kModelDomain = 3   ///< a wheel state left the wear model's or the input limits' domain (message names it)
};
const char* costStatusName(CostStatus status);

/// The cost of one trajectory. Wheel arrays in vehicle order (front_left, front_right, rear_left, rear_right).
struct TrajectoryCost {
  CostStatus status = CostStatus::kBadInput;
  std::string message;              ///< empty when ok; else names the sample, field, value and constraint
  std::size_t bad_sample = 0;       ///< index of the offending sample when status != kOk [-]
  double duration_s = 0.0;          ///< t_last - t_first [s]
  double distance_m = 0.0;          ///< CoG path length [m]
  double total_wear_kg = 0.0;       ///< sum of the wheels [kg]
  double wear_per_distance_kg_per_m = 0.0;  ///< total / distance [kg/m] (1 mg/km = 1e-9 kg/m); 0 if not moving
  std::array<double, kWheelCount> wheel_wear_kg{};       ///< [kg]
  std::array<double, kWheelCount> stick_fraction{};      ///< time-weighted mean [-]
  std::array<double, kWheelCount> slide_fraction{};      ///< 1 - stick_fraction [-]

  bool ok() const { return status == CostStatus::kOk; }
};

/// Per-wheel rates of one instant: what the integrator needs from a direct evaluation or from the map.
struct WheelRates {
  std::array<double, kWheelCount> wear_kg_per_s{};   ///< [kg/s]
  std::array<double, kWheelCount> stick_fraction{};  ///< [-]
};

/// Checks one sample (finite fields, speed >= 0 and <= limits.max_speed_mps, |kappa| and |theta| within their
/// bounds); false with
/// *error "sample <index>: <field> = <value>: must be <constraint>".
bool checkSample(const VehicleWearSetup& setup, const TrajectorySample& sample, std::size_t index,
                 std::string* error);

/// Where the integrator gets each sample's per-wheel rates from: the direct evaluation or the map.
class WheelRateSource {
 public:
  virtual ~WheelRateSource() = default;
  /// Rates at one sample (already checked by checkSample). false with *error naming the wheel or axis and the
  /// field when the sample cannot be evaluated; the cost then carries failureStatus().
  virtual bool rates(const TrajectorySample& sample, WheelRates* rates, std::string* error) const = 0;
  virtual CostStatus failureStatus() const = 0;
};

/// Integrates one trajectory of n samples from a rate source, as the file comment says: validates every sample
/// (checkSample) and the time order first, then sums. Allocates only for an error message.
TrajectoryCost integrateTrajectory(const VehicleWearSetup& setup, const WheelRateSource& source,
                                   const TrajectorySample* samples, std::size_t n);

/// Direct evaluation: the vehicle model and one WearModel per wheel. Not thread-safe (WearModel is not): one per
/// thread. Allocates only in construction and for error messages.
class TrajectoryCostEvaluator : public WheelRateSource {
 public:
  /// @throw std::invalid_argument naming the field for an invalid setup.
  explicit TrajectoryCostEvaluator(const VehicleWearSetup& setup);

  /// Per-wheel rates at one instant (the sample's time stamps the wheel inputs). false with *error naming the
  /// wheel and the field when a wheel state leaves the input limits or the model's domain.
  bool rates(const TrajectorySample& sample, WheelRates* rates, std::string* error) const override;
  CostStatus failureStatus() const override { return CostStatus::kModelDomain; }
  /// The wheel states of the vehicle model at a sample (for tests and tools).
  void wheelStates(const TrajectorySample& sample, VehicleState* state) const;
  /// Cost of one trajectory of n samples.
  TrajectoryCost evaluate(const TrajectorySample* samples, std::size_t n) const {
    return integrateTrajectory(setup_, *this, samples, n);
  }

  /// Sets the preset of every wheel's model (the node's reconfigured preset); the setup keeps the new one.
  void setPreset(Preset preset);
  /// Sets a wheel's tread temperature [degC] (NaN = unknown) for the following evaluations.
  void setTemperature(int wheel, double tread_temperature_c);
  const VehicleWearSetup& setup() const { return setup_; }

 private:
  VehicleWearSetup setup_;
  VehicleModel vehicle_;
  std::array<std::unique_ptr<WearModel>, kWheelCount> models_;
};

}  // namespace tread_wear
