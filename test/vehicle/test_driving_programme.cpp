// A proving-ground programme built into a drive (vehicle/driving_programme.h): distances and speeds of the
// manoeuvres against kinematics worked by hand, corners against their heading change and the driver's lateral bound,
// bank and grade on the road, bad programmes refused; the LEON-T programme against the distances it declares.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "tread_wear/io/driving_programme_csv.h"
#include "tread_wear/vehicle/driving_programme.h"

namespace tread_wear {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Heading change of the route over [s0, s1]: the integral of its curvature (exact for linear segments).
double headingChange(const Route& route, double s0, double s1) {
  double heading = 0.0;
  for (const RouteSegment& seg : route.segments()) {
    const double a = std::max(s0, seg.s_start_m), b = std::min(s1, seg.s_start_m + seg.length_m);
    if (b <= a) continue;
    auto kappa = [&seg](double s) {
      return seg.kappa_start_per_m + (seg.kappa_end_per_m - seg.kappa_start_per_m) * (s - seg.s_start_m) / seg.length_m;
    };
    heading += 0.5 * (kappa(a) + kappa(b)) * (b - a);
  }
  return heading;
}

/// A 1 km oval-like track: straight 400 m, a 180 deg bend of radius 100/pi m (100 m long), straight 400 m, bend.
DrivingProgramme ovalProgramme() {
  const double bend = 100.0;
  Track track{"Oval",
              {{"S1", "straight", 400.0, 0.0, 0.0, 0.0, 0.0, 0},
               {"B1", "bend", bend, 2.0, 4.0, bend / kPi, 180.0, -1},
               {"S2", "straight", 400.0, 0.0, 0.0, 0.0, 0.0, 0},
               {"B2", "bend", bend, 0.0, 0.0, bend / kPi, 180.0, -1}}};
  ProgrammeSection section{"Brake", "braking", "Test", "Oval", 3, 3.0, {}};
  using K = ProgrammeManoeuvreKind;
  // On S1, twice per pass: brake 20 -> 10 m/s at 1 m/s^2 (150 m), speed up again at 2 m/s^2 (75 m), cruise the rest.
  section.manoeuvres = {{"S1", K::kDeceleration, 2, 20.0, 10.0, 0.0, 1.0},
                        {"S1", K::kAcceleration, 2, 10.0, 20.0, 2.0, 0.0},
                        {"S1", K::kConstant, 2, 20.0, 20.0, 0.0, 0.0},
                        {"B1", K::kConstant, 1, 20.0, 20.0, 0.0, 0.0}};
  return {{track}, {section}};
}

TEST(DrivingProgramme, ManoeuvreDistancesAndTimesAsWorkedByHand) {
  const DrivingProgramme programme = ovalProgramme();
  ProgrammeDriveParams params;
  params.smoothing_s = 0.0;  // the cells as they are
  const ProgrammeDrive drive = buildProgrammeDrive(programme, programme.sections.front(), params);
  // Per lap: S1 in two passes of 200 m: 150 m braking (10 s) + 75 m speeding up (5 s) leave -25 m: the constants
  // cannot absorb it, so 25 m of overrun per pass goes on to the next constant. Pass 1: 10 + 5 s; pass 2: the debt
  // of 25 m plus 225 m of manoeuvres in a 200 m pass: debt 50 m, which B1's cruise (100 m) absorbs: B1 50 m at 20 m/s.
  // Then S2 and B2 at 20 m/s: 500 m. Lap: 2 x 15 s + (50 + 500) m / 20 m/s = 57.5 s, 1000 m.
  EXPECT_NEAR(drive.motion.duration_s(), 3 * 57.5, 1e-9);
  EXPECT_NEAR(drive.motion.distance_m(), 3000.0, 1e-6);
  EXPECT_NEAR(drive.unabsorbed_m, 0.0, 1e-9);
  EXPECT_NEAR(drive.lap_length_m, 1000.0, 1e-12);
  // 5 s into the drive the car brakes at 1 m/s^2 from 20 m/s.
  const VehicleMotion m = drive.motion.at(5.0);
  EXPECT_NEAR(m.speed_mps, 15.0, 1e-9);
  EXPECT_NEAR(m.accel_mps2, -1.0, 1e-12);
}

TEST(DrivingProgramme, CornersKeepTheirHeadingChangeAndTheDriversBound) {
  const DrivingProgramme programme = ovalProgramme();
  for (double bound : {4.0, 3.0}) {
    ProgrammeDriveParams params;
    params.max_lateral_accel_mps2 = bound;
    const ProgrammeDrive drive = buildProgrammeDrive(programme, programme.sections.front(), params);
    // Clockwise laps: -2 pi each (the middle lap: the drive's first and last corners are cut by its ends).
    EXPECT_NEAR(headingChange(drive.motion.route(), 1000.0, 2000.0), -2.0 * kPi, 1e-9) << bound;
    // At 20 m/s a radius of 100/pi m is 12.6 m/s^2: widened to v^2 / bound.
    EXPECT_EQ(drive.widened_corners, 2);
    EXPECT_LE(drive.max_lateral_accel_mps2, bound * (1.0 + 1e-6)) << bound;
    EXPECT_GT(drive.max_lateral_accel_mps2, 0.98 * bound) << bound;
    // Mirrored: the same corners turning left.
    params.mirror = true;
    EXPECT_NEAR(headingChange(buildProgrammeDrive(programme, programme.sections.front(), params).motion.route(), 1000.0,
                              2000.0),
                2.0 * kPi, 1e-9);
  }
}

TEST(DrivingProgramme, SlowingForCornersKeepsTheRadiusAndBrakesBeforeThem) {
  const DrivingProgramme programme = ovalProgramme();
  ProgrammeDriveParams params;
  params.slow_for_corners = true;
  params.max_lateral_accel_mps2 = 4.0;
  params.smoothing_s = 0.0;
  const ProgrammeDrive drive = buildProgrammeDrive(programme, programme.sections.front(), params);
  // Radius kept (100/pi m), so the corner speed is sqrt(4 x 100/pi) = 11.28 m/s, reached by braking at 2.94 m/s^2
  // from the programme's 20 m/s and left at 1 m/s^2; the laps keep their length and heading change.
  const double radius_m = 100.0 / kPi, v_corner = std::sqrt(4.0 * radius_m);
  EXPECT_EQ(drive.widened_corners, 0);
  EXPECT_NEAR(drive.motion.distance_m(), 3000.0, 1e-6);
  // Bound: the route's curvature is sampled 1e-9 s inside each break (routeOf), kappa x 1e-9 x 2000 m per break.
  EXPECT_NEAR(headingChange(drive.motion.route(), 1000.0, 2000.0), -2.0 * kPi, 8.0 * 2e-6 / radius_m);
  EXPECT_LE(drive.max_lateral_accel_mps2, 4.0 * (1.0 + 1e-6));
  double min_speed_on_arc = 1e9, max_decel = 0.0, max_accel = 0.0;
  for (double t = 0.0; t <= drive.motion.duration_s(); t += 0.01) {
    const VehicleMotion m = drive.motion.at(t);
    if (std::fabs(m.path_curvature_per_m) > 0.999 / radius_m) min_speed_on_arc = std::min(min_speed_on_arc, m.speed_mps);
    max_decel = std::max(max_decel, -m.accel_mps2);
    max_accel = std::max(max_accel, m.accel_mps2);
  }
  EXPECT_NEAR(min_speed_on_arc, v_corner, 0.01 * v_corner);
  EXPECT_NEAR(max_decel, params.corner_brake_mps2, 1e-9);  // the corners' braking, harder than the programme's 1
  EXPECT_NEAR(max_accel, 2.0, 1e-9);                       // the programme's own 2 m/s^2 kept
  // Slower through the corners: longer than widening them at the programme's speed.
  params.slow_for_corners = false;
  EXPECT_GT(drive.motion.duration_s(),
            buildProgrammeDrive(programme, programme.sections.front(), params).motion.duration_s() + 1.0);
  // A bound the programme never reaches changes nothing.
  params.slow_for_corners = true;
  params.max_lateral_accel_mps2 = 20.0;
  const ProgrammeDrive unbound = buildProgrammeDrive(programme, programme.sections.front(), params);
  params.slow_for_corners = false;
  EXPECT_EQ(unbound.motion.duration_s(), buildProgrammeDrive(programme, programme.sections.front(), params).motion.duration_s());
}

TEST(DrivingProgramme, GradeAndBankFollowTheSectorUnderTheCar) {
  const DrivingProgramme programme = ovalProgramme();
  ProgrammeDriveParams params;
  params.smoothing_s = 0.0;
  const ProgrammeDrive drive = buildProgrammeDrive(programme, programme.sections.front(), params);
  // After S1's two passes (30 s) the car is at 450 m, 50 m into B1 (400-500 m), and cruises at 20 m/s: at 31 s it is
  // at 470 m. B1 turns right, so its bank falls to the right (negative); 4 % lateral and 2 % longitudinal slope.
  const VehicleMotion on_b1 = drive.motion.at(31.0);
  EXPECT_NEAR(on_b1.grade_rad, std::atan(0.02), 1e-12);
  EXPECT_NEAR(on_b1.bank_rad, -std::atan(0.04), 1e-12);
  const VehicleMotion on_s1 = drive.motion.at(1.0);
  EXPECT_EQ(on_s1.grade_rad, 0.0);
  EXPECT_EQ(on_s1.bank_rad, 0.0);
}

TEST(DrivingProgramme, BadProgrammesAreRefusedByName) {
  DrivingProgramme programme = ovalProgramme();
  const ProgrammeDriveParams params;
  auto message = [&params](const DrivingProgramme& p) {
    try {
      buildProgrammeDrive(p, p.sections.front(), params);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  DrivingProgramme no_turn = programme;
  no_turn.tracks[0].sectors[1].turn = 0;
  EXPECT_NE(message(no_turn).find("Oval sector B1: a corner needs a turn direction"), std::string::npos);
  DrivingProgramme bad_repeats = programme;
  bad_repeats.sections[0].manoeuvres[1].repeats = 3;
  EXPECT_NE(message(bad_repeats).find("different repeat counts"), std::string::npos);
  DrivingProgramme speeding_brake = programme;
  speeding_brake.sections[0].manoeuvres[0].end_speed_mps = 25.0;
  EXPECT_NE(message(speeding_brake).find("deceleration S1 to a higher speed"), std::string::npos);
  DrivingProgramme unknown = programme;
  unknown.sections[0].track = "Moon";
  EXPECT_NE(message(unknown).find("unknown track 'Moon'"), std::string::npos);
  DrivingProgramme nan_length = programme;
  nan_length.tracks[0].sectors[0].length_m = std::nan("");
  EXPECT_NE(message(nan_length).find("length must be > 0"), std::string::npos);
  ProgrammeDriveParams bad = params;
  bad.max_lateral_accel_mps2 = 0.0;
  EXPECT_THROW(buildProgrammeDrive(programme, programme.sections.front(), bad), std::invalid_argument);
  ProgrammeDriveParams bad_brake = params;
  bad_brake.corner_brake_mps2 = std::nan("");
  try {
    buildProgrammeDrive(programme, programme.sections.front(), bad_brake);
    ADD_FAILURE() << "a NaN corner braking was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("corner_brake_mps2"), std::string::npos) << e.what();
  }
}

TEST(DrivingProgramme, LeonTSectionsDriveTheirLapsAndKeepTheirHeading) {
  const std::string dir = std::string(TREAD_WEAR_SOURCE_DIR) + "/data/leon_t_idiada";
  const DrivingProgramme programme = readDrivingProgramme(dir, dir + "/turns.csv");
  ASSERT_EQ(programme.sections.size(), 12u);
  for (const char* id : {"Run-in", "Rural_80_kph", "Motorway", "Urban_cs_20kph", "Urban_br_20kph", "Urban_pa_40kph"}) {
    ProgrammeSection section = *programme.section(id);
    section.laps = 3;  // the laps are alike
    const ProgrammeDrive drive = buildProgrammeDrive(programme, section, ProgrammeDriveParams());
    // What overruns a sector is absorbed by the next cruise; only the last lap's overrun is driven beyond the laps.
    // (within a tau^2 a / 24 of the smoothing where the drive ends accelerating)
    EXPECT_NEAR(drive.motion.distance_m(), 3 * drive.lap_length_m + drive.unabsorbed_m, 0.1) << id;
    EXPECT_LT(drive.unabsorbed_m, 0.05 * drive.lap_length_m) << id;
    // A lap of the oval turns -360 deg (clockwise), of the urban loop 0 (a figure eight), of the parking loop 360 deg.
    const double turn = section.track.rfind("Oval", 0) == 0 ? -2.0 * kPi
                        : section.track == "Urban Loop"     ? 0.0
                                                            : 2.0 * kPi;
    const double lap = drive.lap_length_m;
    EXPECT_NEAR(headingChange(drive.motion.route(), lap, 2.0 * lap), turn, 1e-6) << id;
  }
  // The programme's declared totals against laps x lap: within 10 % for every section of the four tests (the data's
  // own rounding; the *_SIML sections are the data authors' simplified model, not driven tests).
  for (const ProgrammeSection& s : programme.sections) {
    if (s.test.find("SIML") != std::string::npos) continue;
    const double built_km = s.laps * programme.track(s.track)->lapLength_m() / 1000.0;
    EXPECT_NEAR(built_km / s.declared_distance_km, 1.0, 0.10) << s.id;
  }
}

}  // namespace
}  // namespace tread_wear
