#pragma once
/// @file wear_characteristics.h
/// Wear characteristics of the paper's Section 4.3 on the Grip and Abrasion Test Stand (circular track):
///  - W_r over side force for several vertical loads (Fig 13a) and several speeds (Fig 15a), by sweeping the
///    slip angle on the track of radius R_t;
///  - W_r over load at a required side force and the optimal load (Fig 13b, Eq 27 "determined through
///    numerical interpolation"): W_r at the side force is interpolated along each load's sweep (rising branch,
///    below the grip peak), and the minimum over loads is refined by a parabola through the best grid load
///    and its neighbours;
///  - W_r over speed at a required side force (Fig 15b) and its local minima (the optimal speed);
///  - the condition v0 sin(alpha) = v_m (Fig 17): for each speed the slip angle alpha_m = asin(v_m / v0), its
///    side force and W_r (the paper's "optimal side force" line).
/// Conventions as the run tables (data/paper/SOURCE.md): slip_angle_rad = -alpha, path radius +R_t, Fy > 0.
/// Limits: steady state, no temperature rise (the paper's footnote 3), the model's own limits.

#include <string>
#include <vector>

#include "tread_wear/model/brush_wear_model.h"

namespace tread_wear {

struct CharacteristicsOptions {
  std::vector<double> loads_n = {25.0, 50.0, 75.0, 100.0, 125.0};  ///< Fig 13 loads [N]
  double load_sweep_speed_mps = 2.0;                                ///< Fig 13 speed [m/s]
  std::vector<double> speeds_mps = {0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0};  ///< [m/s]
  double speed_sweep_load_n = 75.0;                                 ///< Figs 15, 17 load [N]
  double max_slip_angle_deg = 20.0;                                 ///< sweep 0..max [deg]
  double slip_angle_step_deg = 0.5;                                 ///< [deg], > 0
  std::vector<double> side_forces_n = {10.0, 20.0, 30.0, 40.0, 50.0, 60.0};  ///< required side forces [N]
  double track_radius_m = 0.060;                                    ///< R_t (Table 1) [m]
  BrushOptions brush{GridSpec{400, 24, 0.8}, TurnSlipOrientation::kLiteral, false, 2, 1e-14};

  bool validate(std::string* error) const;
};

struct SweepPoint {
  double load_n, speed_mps, slip_angle_deg;
  double side_force_n;
  double wear_rate_kg_per_m;
  double stick_fraction;  ///< Section 4 definition (v_s <= v_m) [-]
};

/// W_r at a required side force along one slip-angle sweep (linear in Fy on the rising branch up to the
/// grip peak); NaN when the side force is not reached.
double wearAtSideForce(const std::vector<SweepPoint>& sweep, double side_force_n);

/// Minimum of y(x) over a grid: the best grid point refined by a parabola through it and its neighbours
/// (vertex clamped to the neighbours' span). at_edge when the best point is the first or last (no refinement).
struct GridMinimum {
  double x = 0.0, y = 0.0;
  bool at_edge = false;
  bool found = false;  ///< false when no finite y
};
GridMinimum refinedMinimum(const std::vector<double>& x, const std::vector<double>& y);

struct WearCharacteristics {
  std::vector<SweepPoint> load_sweeps;   ///< Fig 13a, all loads
  std::vector<SweepPoint> speed_sweeps;  ///< Fig 15a, all speeds
  struct AtSideForce {
    double side_force_n;
    std::vector<double> wear_by_load_kg_per_m;   ///< aligned with options.loads_n (NaN: not reachable)
    std::vector<double> wear_by_speed_kg_per_m;  ///< aligned with options.speeds_mps
    GridMinimum optimal_load;                    ///< Fig 13b
    std::vector<GridMinimum> speed_local_minima; ///< Fig 15b: interior local minima over speed
  };
  std::vector<AtSideForce> at_side_force;
  struct VmCondition {
    double speed_mps, slip_angle_deg, side_force_n, wear_rate_kg_per_m;
  };
  std::vector<VmCondition> vm_condition;  ///< Fig 17: alpha = asin(v_m / v0) where v0 > v_m
};

/// Runs every sweep. @throw std::invalid_argument for invalid params or options.
WearCharacteristics computeWearCharacteristics(const TireParams& params, const CharacteristicsOptions& options);

}  // namespace tread_wear
