#pragma once
/// @file wear_map.h
/// A per-wheel wear map over (v, a_x, a_y) for planner loops: the direct cost (trajectory_cost.h) evaluated once
/// on a grid for the current tires, then interpolated per sample (well under a microsecond instead of four model
/// evaluations).
///
/// Grid: nodes v_i (speed_mps, first > 0), a_x,j (accel_x_mps2) and the lateral share eta_k (lateral_share, in
/// [-1, 1]) of the lateral acceleration reachable at that speed:
///   a_y,max(v) = min(A_y, kappa_max v^2)      (A_y = max_lateral_accel_mps2, kappa_max = the setup's curvature bound)
///   a_y        = eta a_y,max(v),   kappa = a_y / v^2 at the node
/// So the a_y nodes of a speed span what a car can do there: at high speed the tire's grip (A_y), at walking pace the
/// tightest turn (kappa_max), where a_y = v^2 kappa is tiny but turn slip still wears the tires. A uniform a_y axis
/// would put most low-speed nodes in turns no car can make and leave a parking manoeuvre between two nodes.
/// Each node stores per wheel the wear rate wdot_i [kg/s] and the stick fraction s_i [-].
/// Interpolation: trilinear in ln(wdot_i + floor) and linear in s_i over (v, a_x, eta). Wear grows like a power of
/// the slips (Eq 19: |tau|^w1 |v_s|^w2), so its logarithm is close to linear across a cell where wdot itself is
/// strongly convex; the floor (a wheel off the ground wears nothing) keeps the logarithm finite. Wear per time, not
/// per distance: the model's default wear w4 is per time and dominates at low speed.
/// Below the first speed node v_0 (default: WearModel's low-speed threshold, 0.1 m/s) the rates are those of the
/// node times v / v_0, the low-speed convention's linear fall to zero at standstill. A sample beyond the last speed
/// node, outside the a_x axis, with |eta| beyond the lateral axis or on a grade (the map is for a flat road) is an
/// error (CostStatus::kOutsideMap) naming the axis: evaluate such a trajectory directly.
///
/// Error against the direct evaluation: measured, not assumed (bench/planner_bench.cpp, docs/planner.md).
/// Validity: the map holds the setup it was built for (vehicle, tires, temperatures, preset) and its fingerprint
/// (setupFingerprint); a planner that embeds a published map compares fingerprints.
/// Threads: build() runs off any real-time thread (it evaluates the model at every node and allocates);
/// a built map is immutable, so any number of threads may query it; queries allocate nothing except error
/// messages.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tread_wear/planning/trajectory_cost.h"

namespace tread_wear {

struct WearMapParams {
  /// Speed nodes [m/s], strictly increasing, first > 0: from the low-speed threshold through walking pace, 0.5 m/s
  /// steps to 6 m/s (the lateral axis reaches kappa_max v^2 there, so a node's a_y changes fastest with v), 2.5 m/s
  /// steps above 10 m/s.
  std::vector<double> speed_mps = {0.1,  0.25, 0.5,  1.0,  1.5,  2.0,  2.5,  3.0,  3.5,  4.0,  4.5,  5.0,  5.5,
                                   6.0,  7.0,  8.0,  10.0, 12.5, 15.0, 17.5, 20.0, 22.5, 25.0, 27.5, 30.0, 32.5,
                                   35.0, 37.5, 40.0, 42.5, 45.0};
  /// Longitudinal acceleration nodes [m/s^2], strictly increasing: -8 (hard braking) to +5, every 0.25 within
  /// +-3 m/s^2 and every 0.5 beyond. Wear rises steeply from its minimum near zero drive force (Eq 19 on the driven
  /// wheels' slip), where ln(wdot) bends most: 0.5 m/s^2 cells there cost up to 13 % per sample, 0.25 about 3 %
  /// (docs/planner.md).
  std::vector<double> accel_x_mps2 = {-8.0,  -7.5, -7.0,  -6.5, -6.0,  -5.5, -5.0,  -4.5, -4.0, -3.5,
                                      -3.0,  -2.75, -2.5, -2.25, -2.0, -1.75, -1.5, -1.25, -1.0, -0.75,
                                      -0.5,  -0.25, 0.0,  0.25,  0.5,  0.75,  1.0,  1.25,  1.5,  1.75,
                                      2.0,   2.25, 2.5,   2.75,  3.0,  3.5,   4.0,  4.5,   5.0};
  /// Lateral share nodes eta [-], strictly increasing in [-1, 1] (file comment), every 1/36 (0.25 m/s^2 at speed).
  std::vector<double> lateral_share = uniformAxis(-1.0, 1.0, 73);
  double max_lateral_accel_mps2 = 9.0;  ///< A_y, reach of the lateral axis at speed [m/s^2], > 0 (beyond a road
                                        ///< tire's grip)
  double wear_floor_kg_per_s = 1e-15;   ///< floor added before the logarithm [kg/s], > 0 (a road car's tire wears
                                        ///< ~1e-7 kg/s at cruise: eight decades above)
  int build_threads = 1;                ///< threads of build() [-], >= 1 (the node keeps 1: two cores are shared)

  /// n nodes from first to last, equally spaced.
  static std::vector<double> uniformAxis(double first, double last, int n);
  /// false with *error "<field> = <value>: must be <constraint>" for the first broken constraint.
  bool validate(std::string* error) const;
};

class WearMap : public WheelRateSource {
 public:
  /// Builds the map for `setup`. cancel (optional) aborts the build when set (returns nullptr).
  /// @throw std::invalid_argument naming the field for an invalid setup or params;
  /// @throw std::runtime_error naming the node when the model cannot be evaluated there.
  static std::shared_ptr<const WearMap> build(const VehicleWearSetup& setup, const WearMapParams& params,
                                              const std::atomic<bool>* cancel = nullptr);

  /// Per-wheel rates at one sample, interpolated; false with *error naming the axis when outside the map.
  bool rates(const TrajectorySample& sample, WheelRates* rates, std::string* error) const override;
  CostStatus failureStatus() const override { return CostStatus::kOutsideMap; }
  /// Cost of one trajectory from the map (same validation and integration as the direct evaluation).
  TrajectoryCost evaluate(const TrajectorySample* samples, std::size_t n) const {
    return integrateTrajectory(setup_, *this, samples, n);
  }

  const VehicleWearSetup& setup() const { return setup_; }
  const WearMapParams& params() const { return params_; }
  std::uint64_t fingerprint() const { return fingerprint_; }
  double buildTime_s() const { return build_time_s_; }  ///< wall time of build() [s]
  std::size_t nodeCount() const { return nodes_; }

  /// Node index of (speed i, a_x j, lateral share k): ((i * n_ax) + j) * n_eta + k.
  std::size_t nodeIndex(std::size_t i, std::size_t j, std::size_t k) const {
    return (i * params_.accel_x_mps2.size() + j) * params_.lateral_share.size() + k;
  }
  /// a_y,max(v) = min(A_y, kappa_max v^2) [m/s^2].
  double maxLateralAccel_mps2(double speed_mps) const;
  /// eta of a sample: v^2 kappa / a_y,max(v), or kappa / kappa_max where kappa_max v^2 <= A_y (also at v = 0) [-].
  double lateralShare(double speed_mps, double path_curvature_per_m) const;
  /// CoG path curvature at speed node i and lateral node k [1/m].
  double nodeCurvature_per_m(std::size_t i, std::size_t k) const;
  /// Wear rate of a wheel at a node [kg/s].
  double nodeWearRate_kg_per_s(int wheel, std::size_t node) const;
  /// Stick fraction of a wheel at a node [-].
  double nodeStickFraction(int wheel, std::size_t node) const {
    return values_[node * kValuesPerNode + kWheelCount + static_cast<std::size_t>(wheel)];
  }

 private:
  WearMap(const VehicleWearSetup& setup, const WearMapParams& params);
  /// ln(wdot + floor) for each wheel, then the stick fraction for each wheel.
  static constexpr std::size_t kValuesPerNode = 2 * kWheelCount;

  VehicleWearSetup setup_;
  WearMapParams params_;
  std::uint64_t fingerprint_ = 0;
  double build_time_s_ = 0.0;
  std::size_t nodes_ = 0;
  std::vector<double> values_;  ///< kValuesPerNode per node, node-major
};

}  // namespace tread_wear
