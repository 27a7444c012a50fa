#pragma once
/// @file driving_programme.h
/// A proving-ground driving programme (tracks of sectors, test sections of laps and manoeuvres; the LEON-T IDIADA
/// programme of data/leon_t_idiada, read by io/driving_programme_csv.h) built into a drive that tread_wear_drive
/// writes as a bag like any other (docs/measured_road_wear.md).
///
/// The data's semantics (its README; the data authors' R/SIML_dataprep.R):
///   - a test section is `laps` laps of its track; a lap is the track's sectors in order;
///   - in each sector the section's manoeuvres for that sector run in order, and the sequence is driven `repeats`
///     times per pass of the sector (all manoeuvres of a sector share one repeat count: a deceleration and the
///     acceleration back are one repeat);
///   - an acceleration runs from the current speed to its end speed at its constant a over (v1^2 - v0^2) / (2 a), a
///     deceleration likewise at d; the Constant manoeuvres share the rest of the sector's distance equally;
///   - a corner sector turns by its angle at radius R over its length (R x angle = length).
/// Assumptions this builder adds (each a field of ProgrammeDriveParams or of the turn table, with its effect
/// measured in docs/measured_road_wear.md):
///   - direction of travel: per corner sector from the turn table (`turn` of ProgrammeSector: +1 left, -1 right),
///     the whole programme mirrored with `mirror`;
///   - the driver's path through a corner keeps the corner's heading change but not necessarily its radius: the
///     radius is widened to R' = max(R, v_max^2 / max_lateral_accel_mps2) (v_max the largest speed on the corner), and
///     curvature ramps in and out over clothoids of length min(v_max steer_transition_s, R' angle), so the path
///     is longer than the sector by the transition; the extra length is taken from the neighbouring sectors
///     (the corner stays centred on its sector). Overlapping corners add their curvatures (heading changes kept).
///     With slow_for_corners the radius is kept instead and the speed bounded by sqrt(bound R) over the corner and
///     its clothoids, braking before at corner_brake_mps2 and accelerating after at corner_accel_mps2 (the
///     distance-domain forward-backward bound of lap-time simulation; the programme's own constants kept);
///   - a manoeuvre that needs more distance than its sector has runs on into the next sector, whose Constant
///     manoeuvres are shortened by the overrun (the lap keeps its length; what no Constant manoeuvre could absorb
///     is reported as ProgrammeDrive::unabsorbed_m);
///   - a manoeuvre starts from the speed where the previous one ended (the data's start speeds differ by rounding);
///   - bank: a corner's lateral slope falls towards the inside of the turn; a straight's falls to the right of
///     travel (a crossfall towards the verge in right-hand traffic). Slopes are percent (the data authors divide by
///     100), angles atan(slope/100);
///   - speed steps between cells are smoothed over smoothing_s (drive_motion.h: bounded jerk, distances kept).
/// Limits: the section starts at its first manoeuvre's start speed (no run-up), and between sections the car is
/// not driven (each section is its own drive). Sign conventions: ISO 8855, kappa > 0 turning left.

#include <string>
#include <vector>

#include "tread_wear/vehicle/drive_motion.h"

namespace tread_wear {

/// One sector of a track.
struct ProgrammeSector {
  std::string id;                  ///< sector number of the data ("OIL1")
  std::string name;                ///< its name ("North Straight")
  double length_m = 0.0;           ///< distance along the sector [m], > 0
  double grade_percent = 0.0;      ///< longitudinal slope [%], > 0 uphill
  double crossfall_percent = 0.0;  ///< lateral slope magnitude [%] (side: see the file comment)
  double radius_m = 0.0;           ///< corner radius [m]; 0: straight
  double angle_deg = 0.0;          ///< corner angle [deg], >= 0
  int turn = 0;                    ///< +1 left, -1 right (corners only; 0 for straights)
};

enum class ProgrammeManoeuvreKind { kAcceleration = 0, kDeceleration = 1, kConstant = 2 };

/// One manoeuvre of a test section in one sector.
struct ProgrammeManoeuvre {
  std::string sector_id;
  ProgrammeManoeuvreKind kind = ProgrammeManoeuvreKind::kConstant;
  int repeats = 1;               ///< repeats of the sector's manoeuvre sequence per pass [-], >= 1
  double start_speed_mps = 0.0;  ///< [m/s]
  double end_speed_mps = 0.0;    ///< target speed of an acceleration or deceleration [m/s], >= 0
  double accel_mps2 = 0.0;       ///< acceleration constant [m/s^2], > 0 for an acceleration
  double decel_mps2 = 0.0;       ///< deceleration constant, a positive number [m/s^2], > 0 for a deceleration
};

/// One test section: laps of a track with its manoeuvres.
struct ProgrammeSection {
  std::string id;                              ///< test section ("Rural_60_kph")
  std::string name;                            ///< section name ("Rural driving at 60 kph")
  std::string test;                            ///< abrasion test it belongs to ("Rural")
  std::string track;                           ///< track name ("Oval Inner Lane")
  int laps = 0;                                ///< [-], >= 1
  double declared_distance_km = 0.0;           ///< total distance the programme states [km]
  std::vector<ProgrammeManoeuvre> manoeuvres;  ///< in order
};

struct Track {
  std::string name;
  std::vector<ProgrammeSector> sectors;  ///< one lap, in order
  double lapLength_m() const;
};

struct DrivingProgramme {
  std::vector<Track> tracks;
  std::vector<ProgrammeSection> sections;

  /// nullptr when absent.
  const Track* track(const std::string& name) const;
  const ProgrammeSection* section(const std::string& id) const;
  /// Every section's track exists, every manoeuvre's sector is on it, and the numbers are in range; false with
  /// "<section or track>: <what is wrong>" for the first problem.
  bool validate(std::string* error) const;
};

/// The builder's own assumptions (file comment).
struct ProgrammeDriveParams {
  double max_lateral_accel_mps2 = 4.0;  ///< driver's bound on v^2 kappa in corners [m/s^2], > 0
  /// How the driver keeps a corner within max_lateral_accel_mps2 where the programme's speed would exceed it:
  /// false widens the radius (speed kept), true keeps the radius and slows to sqrt(bound R) over the corner,
  /// braking before it at corner_brake_mps2 and accelerating after it at corner_accel_mps2.
  bool slow_for_corners = false;
  double corner_brake_mps2 = 2.94;  ///< deceleration into a corner driven slower [m/s^2], > 0
  double corner_accel_mps2 = 1.0;   ///< acceleration out of it [m/s^2], > 0
  double steer_transition_s = 1.0;      ///< clothoid length = v_max x this [s], >= 0
  double smoothing_s = 1.0;             ///< speed-trace smoothing window tau (drive_motion.h) [s], >= 0
  bool mirror = false;                  ///< drive every corner the other way

  bool validate(std::string* error) const;
};

/// Grade and bank of the road from a distance on [s_start, s_end).
struct RoadPiece {
  double s_start_m = 0.0;
  double s_end_m = 0.0;
  double grade_rad = 0.0;  ///< > 0 uphill
  double bank_rad = 0.0;   ///< > 0 left edge lower
};

/// A speed trace over its route with the road's grade and bank at the distance driven.
class ProgrammeMotion : public DriveMotion {
 public:
  ProgrammeMotion(SpeedTrace trace, std::vector<RoadPiece> road) : trace_(std::move(trace)), road_(std::move(road)) {}
  double startTime_s() const override { return trace_.startTime_s(); }
  double duration_s() const override { return trace_.duration_s(); }
  double distance_m() const override { return trace_.distance_m(); }
  VehicleMotion at(double t_s) const override;
  const Route& route() const override { return trace_.route(); }
  const SpeedTrace& trace() const { return trace_; }

 private:
  SpeedTrace trace_;
  std::vector<RoadPiece> road_;  ///< sorted, contiguous
};

/// A built section with what the builder did to it.
struct ProgrammeDrive {
  ProgrammeMotion motion;
  double lap_length_m = 0.0;            ///< the track's lap [m]
  double unabsorbed_m = 0.0;            ///< manoeuvre distance beyond the section's laps [m]
  int widened_corners = 0;              ///< corners per lap whose radius the lateral bound widened [-]
  double max_lateral_accel_mps2 = 0.0;  ///< largest |v^2 kappa| over the drive (sampled at 10 Hz) [m/s^2]
};

/// Builds a test section on its track of the programme (a section of the programme, or a copy with other laps).
/// @throw std::invalid_argument naming the problem (unknown track, invalid programme or params, no manoeuvres, laps
///        < 1, a Constant manoeuvre at standstill, an acceleration to a lower or a deceleration to a higher speed)
ProgrammeDrive buildProgrammeDrive(const DrivingProgramme& programme, const ProgrammeSection& section,
                                   const ProgrammeDriveParams& params);

}  // namespace tread_wear
