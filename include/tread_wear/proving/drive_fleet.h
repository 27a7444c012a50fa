#pragma once
/// @file drive_fleet.h
/// The concealed-effect generator's drive design (`drives`, conceal.h): road drives of a few vehicles whose tires'
/// wear is measured at checkpoints every few thousand kilometres on every wheel, so that the diagnosis is proved on
/// drive segments (extensions.h: a run with drive points) as well as on rig runs.
///
/// Per vehicle, `checkpoints` wear measurements on every wheel; a segment (between two) is about
/// segment_distance_m of repetitions of one cycle (the WLTC class 3b profile) under the segment's conditions:
///   season     ambient T_a = 11 - 9 cos(2 pi month / 12) + N(0, 1.5^2) degC (a central European year), month = the
///              segment's middle, each segment two months (3000 km at 18000 km a year), the vehicle's first month
///              U(0, 12)
///   style      the cycle's speeds x U(0.92, 1.05) (same times: distance scales too), driven within the `normal`
///              envelope (driving_style.h) x U(0.7, 1.4) (a_max, d_max, a_y,max; at most 8 m/s^2)
///   payload    U(0, payload_max_kg) kg on the vehicle's mass (CoG kept: vehicle_model.h)
///   road       rough_road_share U(0.05, 0.65): share of the distance on coarse asphalt (recorded; no library term
///              reads it: the drive design's out-of-library effect `rough_road`)
/// The route (route.h, seed per vehicle) and the vehicle model (vehicle_model.h) turn the driven profile into each
/// wheel's load, slip angle, slip ratio, path curvature and speed, sampled at update_rate_hz and fed to a
/// DriveSegmenter (estimation/drive_segments.h) with the replay's grid and integration rule at the same rate.
/// The quasi-steady vehicle model is deterministic, so every repetition of the cycle under one segment's conditions
/// gives the same inputs: ONE cycle is simulated per (vehicle, segment) and its time and distance weights are
/// multiplied by the number of repetitions, round(segment_distance_m / cycle distance) >= 1 (each repetition
/// starts cold, as the simulated cycle does).
/// Cells: the points are binned far coarser than point_cells.h's defaults (fleetCells(): about 80 cells per
/// wheel and segment instead of about 4500), so that a case costs minutes: at the defaults 72 segments gave 324k
/// cells, and one prediction at `reference` (about 3 ms a cell) a quarter of an hour. The truth and the diagnosis
/// see the same cells, so the binning is part of the case, not an error of the proof; what binning costs against
/// the step-by-step replay is the replay check's (docs/diagnosis.md, "Drives between measurements").
/// Tread temperature, recorded as the wheel's temperature input (so the points carry it): a first-order lag
///   dT/dt = (T_ss - T) / tau,  T_ss = T_a + o + k (f_r Fz V + |Fy| V |sin alpha| + |Fx| V |kappa|),  T(0) = T_a + o,
/// the heat of rolling resistance plus the slip power of the force demands (vehicle_model.h: no tire model is
/// evaluated), k = 0.015 degC/W, tau = 300 s, o ~ N(0, 1^2) degC per wheel and segment (tire and sensor
/// placement). A simple proxy (not a thermal model of the tire): about +6 degC in town, +18 degC on the motorway.
/// The truth (conceal.h): the base model with the w3_scale and mu_scale jitter plus the hidden effect, evaluated by
/// ExtendedModel on the segments' cells at the spec's preset. Hidden effects: a library term (thermal_wear: T0 =
/// 35 degC, sigma_T = magnitude), or `rough_road`: wear x (1 + beta (rough_road_share - 0.35)), beta = magnitude
/// (0.35 is the design's mean share). Measured per segment: the wear rate W_r = mass loss / distance, with
///   - the relative noise x (1 + N(0, wear_noise_rsd^2)) of weighing the tire (ConcealSpec), and
///   - a tread-depth gauge: each checkpoint's reading + N(0, depth_gauge_sigma_m^2), loss = the difference of two
///     readings x MaterialParams::massPerDepth_kg_per_m (neighbouring segments share a reading);
/// a measured rate is floored at 5% of the truth (the diagnosis needs W_r > 0). No side force on drives.
/// Recorded per run: the segment's means (speed, load, |alpha|, |kappa|, |1/R|, tread temperature: DriveSegment),
/// the load std, and the covariates ambient_c, rough_road_share, payload_kg, speed_scale, accel_scale,
/// odometer_km (segment middle), with the text covariates vehicle and wheel; condition_id = vehicle/segment (the
/// four wheels of a segment are held out together); no cycle or run order (a road has no surface cycles).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tread_wear/io/run_table.h"
#include "tread_wear/model/point_cells.h"
#include "tread_wear/vehicle/speed_profile.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {
namespace diagnosis {

/// Mean rough_road_share of the design; `rough_road`'s factor is 1 there [-].
constexpr double kRoughRoadMeanShare = 0.35;
/// The drive design's out-of-library effect (no library term): wear x (1 + beta (rough_road_share - mean)).
constexpr const char* kRoughRoadEffect = "rough_road";

/// The drive design's cells (point_cells.h's asinh widths): load 0.7 (a bin per factor of about 2 above 100 N),
/// |alpha| and |kappa| 2.5 above 1e-3, speed 1.5 above 1 m/s, |1/R| 3 above 1e-3 1/m, tread temperature 10 degC.
PointCellParams fleetCells();

/// The fleet and measurement plan of the drive design.
struct DriveFleet {
  std::vector<VehicleParams> vehicles;          ///< at least one, each valid
  std::shared_ptr<const SpeedProfile> profile;  ///< the cycle repeated (WLTC class 3b), not null
  int checkpoints = 4;                          ///< measurements per wheel, >= 2 (segments = checkpoints - 1)
  double segment_distance_m = 3.0e6;            ///< distance between checkpoints [m], > 0 (whole cycles)
  double update_rate_hz = 10.0;                 ///< input samples and segmenter steps [Hz], in [1, 100]
  double payload_max_kg = 300.0;                ///< largest payload of a segment [kg], >= 0
  double depth_gauge_sigma_m = 0.0;             ///< tread-depth reading noise [m], >= 0 (0: weighed only)
  /// Cells of the segments' points (point_cells.h); coarser than the defaults (see the file comment)
  PointCellParams cells = fleetCells();

  /// Names the first field that is missing or out of range.
  bool validate(std::string* error) const;
};

/// One simulated (vehicle, segment): its conditions and the four wheels' runs (measurements not yet set).
struct DriveSegmentRuns {
  int vehicle = 0, segment = 0;
  int repetitions = 0;            ///< cycles in the segment [-]
  double cycle_distance_m = 0.0;  ///< CoG distance of one driven cycle [m]
  std::vector<RunRecord> runs;    ///< one per wheel, wheel order of vehicle_model.h
};

/// The runs of the drive design (four per vehicle and segment; covariate names in *table), measurements NaN.
/// `seed` draws the conditions. @throw std::invalid_argument naming the field for an invalid fleet.
std::vector<DriveSegmentRuns> simulateDriveFleet(const DriveFleet& fleet, std::uint64_t seed, RunTable* table);

/// The measured wear rates of the runs of `segments` (in their order, as in the table) from the true ones: the tire
/// weighed with relative noise wear_noise_rsd and, with depth_gauge_sigma_m > 0, the tread-depth readings (file
/// comment). mass_per_depth_kg_per_m: MaterialParams::massPerDepth_kg_per_m of the tire.
std::vector<double> measureDriveWear(const std::vector<DriveSegmentRuns>& segments,
                                     const std::vector<double>& true_wear_kg_per_m, double wear_noise_rsd,
                                     double depth_gauge_sigma_m, double mass_per_depth_kg_per_m, std::uint64_t seed);

}  // namespace diagnosis
}  // namespace tread_wear
