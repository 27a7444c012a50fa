// The published road-wear relations that are well established, pinned on the road tire and the reference car
// (docs/road_validation.md gives each relation, its published value and source). Each expectation is the
// published range or direction itself; the relations the model misses are documented there, not tested here.
// Costs come from the planner's direct evaluation (VehicleModel -> evaluateInputs -> WearModel per wheel).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tread_wear/io/params_io.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/planning/trajectory_cost.h"
#include "tread_wear/vehicle/drive_motion.h"
#include "tread_wear/vehicle/driving_style.h"
#include "tread_wear/vehicle/route.h"

namespace tread_wear {
namespace {

const std::string kSrc = TREAD_WEAR_SOURCE_DIR;
constexpr double kMgPerKm = 1e9;  // [kg/m] -> [mg/km]
constexpr double kSampleStep_s = 0.2;

VehicleWearSetup passengerCar() {
  VehicleWearSetup setup;
  setup.vehicle = loadVehicleParams(kSrc + "/config/vehicle_passenger_car.yaml");
  setup.tires.fill(loadTireParams(kSrc + "/config/tires/passenger_205_55_r16.yaml"));
  return setup;
}

/// Vehicle wear per km of a steady state [mg/km].
double steadyMgPerKm(const TrajectoryCostEvaluator& car, double speed_mps, double accel_mps2, double lateral_mps2) {
  const double kappa = lateral_mps2 / (speed_mps * speed_mps);
  const TrajectorySample samples[] = {{0.0, speed_mps, accel_mps2, kappa}, {1.0, speed_mps, accel_mps2, kappa}};
  const TrajectoryCost cost = car.evaluate(samples, 2);
  EXPECT_TRUE(cost.ok()) << cost.message;
  return cost.wear_per_distance_kg_per_m * kMgPerKm;
}

/// Least-squares slope of ln y over ln x.
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += std::log(x[i]) / x.size(), my += std::log(y[i]) / y.size();
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
    sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
  }
  return sxy / sxx;
}

/// A drive sampled every kSampleStep_s between t0 and t1 (drive time) [s].
std::vector<TrajectorySample> sampled(const DriveMotion& motion, double t0_s, double t1_s) {
  std::vector<TrajectorySample> samples;
  for (double t = t0_s; t <= t1_s + 1e-9; t += kSampleStep_s) {
    const VehicleMotion m = motion.at(motion.startTime_s() + t);
    samples.push_back({t, m.speed_mps, m.accel_mps2, m.path_curvature_per_m});
  }
  return samples;
}

class WltcDrive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    profile_ = new SpeedProfile(loadSpeedProfile(kSrc + "/data/wltc_class3b.csv"));
    motion_ = new ProfileMotion(*profile_, buildRoute(*profile_, RouteParams()));
  }
  static void TearDownTestSuite() {
    delete motion_;
    delete profile_;
  }
  static TrajectoryCost cost(const VehicleWearSetup& setup, double t0_s, double t1_s) {
    const std::vector<TrajectorySample> samples = sampled(*motion_, t0_s, t1_s);
    const TrajectoryCost c = TrajectoryCostEvaluator(setup).evaluate(samples.data(), samples.size());
    EXPECT_TRUE(c.ok()) << c.message;
    return c;
  }
  static TrajectoryCost whole(const VehicleWearSetup& setup) { return cost(setup, 0.0, motion_->duration_s()); }
  static double axleRatio(const TrajectoryCost& c, int first, int second) {
    return (c.wheel_wear_kg[first] + c.wheel_wear_kg[first + 1]) /
           (c.wheel_wear_kg[second] + c.wheel_wear_kg[second + 1]);
  }

  static SpeedProfile* profile_;
  static ProfileMotion* motion_;
};
SpeedProfile* WltcDrive::profile_ = nullptr;
ProfileMotion* WltcDrive::motion_ = nullptr;

// Veith 1986 (Driving Severity Number: treadwear ~ sum of a_y^2, R >= 0.95) and RCT 46(4):821 (1973, wear ~ force^n,
// n = 2-4): cornering wear grows at least with the square of the lateral acceleration.
TEST(RoadRelations, CorneringWearGrowsAtLeastWithTheSquareOfLateralAcceleration) {
  const TrajectoryCostEvaluator car(passengerCar());
  const double v = 60.0 / 3.6, straight = steadyMgPerKm(car, v, 0.0, 0.0);
  const std::vector<double> a_y = {1.0, 1.5, 2.0, 3.0, 4.0};
  std::vector<double> excess;
  for (double a : a_y) excess.push_back(steadyMgPerKm(car, v, 0.0, a) - straight);
  for (std::size_t i = 1; i < a_y.size(); ++i)
    EXPECT_GE(excess[i] / excess[i - 1], std::pow(a_y[i] / a_y[i - 1], 2.0)) << "a_y " << a_y[i];
  EXPECT_GE(logLogSlope(a_y, excess), 2.0);
}

// The same energy argument for driving and braking forces (Schallamach & Turner 1960: abrasion ~ friction energy
// ~ F^2 / C per distance): the wear the force adds, over the straight cruise at the same speed (as for cornering),
// grows at least with the square of |a_x|.
TEST(RoadRelations, DrivingAndBrakingWearGrowAtLeastWithTheSquareOfAcceleration) {
  const TrajectoryCostEvaluator car(passengerCar());
  const double v = 50.0 / 3.6, straight = steadyMgPerKm(car, v, 0.0, 0.0);
  for (double sign : {1.0, -1.0}) {
    const std::vector<double> a_x = {0.5, 1.0, 2.0, 3.0};
    std::vector<double> excess;
    for (double a : a_x) excess.push_back(steadyMgPerKm(car, v, sign * a, 0.0) - straight);
    EXPECT_GE(logLogSlope(a_x, excess), 2.0) << (sign > 0 ? "driving" : "braking");
  }
}

// Pohrt 2019 (review: lower speed is the most effective way to less wear): steady cruise wear per km does not fall
// over the span of cruise speeds, as the rig's per-time term made it do (85 mg/km at 2 m/s against 4.2 at 40 m/s),
// and it rises at motorway speeds. Between 30 and 50 km/h it may dip by a few percent: the drive force's shear
// first cancels part of the free-rolling tread-band shear in the rear half of the patch (model/adhesion_wear.h).
TEST(RoadRelations, CruiseWearPerKmDoesNotFallWithSpeed) {
  const TrajectoryCostEvaluator car(passengerCar());
  auto cruise = [&car](double kmh) { return steadyMgPerKm(car, kmh / 3.6, 0.0, 0.0); };
  EXPECT_GE(cruise(130.0), cruise(30.0));
  double previous = cruise(80.0);
  for (double kmh : {100.0, 120.0, 130.0}) {
    EXPECT_GE(cruise(kmh), previous) << kmh << " km/h";
    previous = cruise(kmh);
  }
}

// The calibration's cited figures: ADAC 2022 (58-160 g per 1000 km per car = 14.5-40 mg/km per tire) and OeAMTC
// (52-82 mg/km per tonne) hold for the WLTC drive of the 1450 kg car.
TEST_F(WltcDrive, LevelIsInsideTheRoadMeasurements) {
  const VehicleWearSetup setup = passengerCar();
  const TrajectoryCost c = whole(setup);
  const double vehicle_mg_per_km = c.wear_per_distance_kg_per_m * kMgPerKm;
  EXPECT_GE(vehicle_mg_per_km / 4.0, 14.5);
  EXPECT_LE(vehicle_mg_per_km / 4.0, 40.0);
  EXPECT_GE(vehicle_mg_per_km / (setup.vehicle.mass_kg / 1000.0), 52.0);
  EXPECT_LE(vehicle_mg_per_km / (setup.vehicle.mass_kg / 1000.0), 82.0);
}

// Fleet experience and TST 1(1):17 (1973): front drive wears the front axle most; rear drive wears the axles more
// evenly (the rear/front ratio moves towards the rear; with the adhesion zone's background on every wheel the
// heavier, steered front axle can still lead, docs/road_validation.md relation 7).
TEST_F(WltcDrive, DrivenAxleWearsMost) {
  VehicleWearSetup setup = passengerCar();
  setup.vehicle.drive_layout = DriveLayout::kFront;
  const double front_over_rear_fwd = axleRatio(whole(setup), kFrontLeft, kRearLeft);
  EXPECT_GT(front_over_rear_fwd, 1.0);
  setup.vehicle.drive_layout = DriveLayout::kRear;
  const double rear_over_front_rwd = axleRatio(whole(setup), kRearLeft, kFrontLeft);
  EXPECT_GT(rear_over_front_rwd, 1.0 / front_over_rear_fwd);                                      // towards the rear
  EXPECT_LT(std::fabs(std::log(rear_over_front_rwd)), std::fabs(std::log(front_over_rear_fwd)));  // more evenly
}

// EMEP/EEA guidebook (S_T = 1.39 below 40 km/h, 0.902 above 90 km/h) and Beddows & Harrison 2021 (urban 8.2,
// motorway 5.5 mg/km): urban driving wears more per km than motorway driving. WLTC class 3b phases: Low 0-589 s,
// Extra High 1478-1800 s.
TEST_F(WltcDrive, UrbanWearsMorePerKmThanMotorway) {
  const VehicleWearSetup setup = passengerCar();
  EXPECT_GT(cost(setup, 0.0, 589.0).wear_per_distance_kg_per_m, cost(setup, 1478.0, 1800.0).wear_per_distance_kg_per_m);
}

// Beddows & Harrison 2021, OeAMTC's per-tonne normalisation, Emissions Analytics 2022: a heavier car wears more.
TEST_F(WltcDrive, HeavierCarWearsMore) {
  VehicleWearSetup setup = passengerCar();
  double previous = 0.0;
  for (double mass : {1200.0, 1450.0, 1800.0}) {
    setup.vehicle.mass_kg = mass;
    const double wear = whole(setup).wear_per_distance_kg_per_m;
    EXPECT_GT(wear, previous) << mass << " kg";
    previous = wear;
  }
}

// Emissions Analytics 2022, BTMA: an aggressive driver wears more than a calm one on the same route.
TEST_F(WltcDrive, AggressiveDrivingWearsMoreThanCalm) {
  const TrajectoryCostEvaluator car(passengerCar());
  double per_km[2];
  const char* styles[] = {"calm", "aggressive"};
  for (int i = 0; i < 2; ++i) {
    DrivingEnvelope envelope;
    ASSERT_TRUE(drivingStyle(styles[i], &envelope));
    const EnvelopeDrive drive = driveWithinEnvelope(*profile_, motion_->route(), envelope);
    const std::vector<TrajectorySample> samples = sampled(drive.trace, 0.0, drive.trace.duration_s());
    const TrajectoryCost c = car.evaluate(samples.data(), samples.size());
    ASSERT_TRUE(c.ok()) << c.message;
    per_km[i] = c.wear_per_distance_kg_per_m;
  }
  EXPECT_GT(per_km[1], per_km[0]);
}

}  // namespace
}  // namespace tread_wear
