// The road wear terms of the library (extensions.h): contact_time_wear adds w4 4ab/V per distance, checked against
// that closed form summed over each segment's own points (not the cells the model bins them into); adhesion_wear
// adds a wear linear in its coefficient; both apply to drive segments only. And the cross-validation by whole
// groups of a recorded covariate (data.h, holdOutGroups), each held-out group calibrated on its own runs of one level
// (calibrateHeldOutGroupsOn).
#include <gtest/gtest.h>

#include <cmath>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/io/params_io.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

TireParams roadTire() {
  return loadTireParams(std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/suv_225_60_r18.yaml");
}

/// Six drive segments of three points each, far apart in load and speed (each point its own cell), with a text
/// covariate `brand` (two segments per brand).
RunTable driveTable() {
  RunTable t;
  t.covariate_names = {"distance_m"};
  t.text_covariate_names = {"brand"};
  const char* brands[] = {"A", "A", "B", "B", "C", "C"};
  for (int i = 0; i < 6; ++i) {
    RunRecord r;
    double time = 0.0, distance = 0.0;
    for (int k = 0; k < 3; ++k) {
      WeightedOperatingPoint p;
      p.op.load_n = 3000.0 + 1500.0 * k + 100.0 * i;
      p.op.speed_mps = 8.0 + 9.0 * k + 0.5 * i;
      p.op.slip_angle_rad = 0.004 * (k + 1);
      p.op.slip_ratio = 0.002 * k;
      p.time_s = 10.0 + 5.0 * k;
      p.distance_m = p.time_s * p.op.speed_mps;
      time += p.time_s;
      distance += p.distance_m;
      r.drive_points.push_back(p);
    }
    r.op = r.drive_points[1].op;
    r.drive_time_s = time;
    r.drive_distance_m = distance;
    r.measured_wear_rate_kg_per_m = 1e-7 * (1.0 + 0.1 * i);
    r.condition_id = "segment_" + std::to_string(i + 1);
    r.run_order = i + 1;
    r.covariates = {distance};
    r.text_covariates = {brands[i]};
    t.runs.push_back(r);
  }
  return t;
}

}  // namespace

TEST(RoadTerms, ContactTimeWearAddsW4TimesContactAreaOverSpeed) {
  const TireParams tire = roadTire();
  ASSERT_EQ(tire.wear.w4_kg_per_s_m2, 0.0);  // the road file wears by sliding only
  const RunTable table = driveTable();
  const DiagnosisData data = buildDiagnosisData(table);
  ASSERT_TRUE(termApplicable(Term::kContactTimeWear, data, nullptr));
  const ExtendedModel base(tire, {}, {}, data);
  const ExtendedModel with(tire, {}, {Term::kContactTimeWear}, data);
  Prediction p0, p1;
  ASSERT_TRUE(base.predict({1.0, 1.0}, &p0));
  const double w4 = 3e-5;  // kg/(s m^2)
  ASSERT_TRUE(with.predict({1.0, 1.0, w4}, &p1));
  for (std::size_t i = 0; i < table.runs.size(); ++i) {
    // Eq 19's w4 term per distance, over the segment's points: sum w4 4 a(Fz) b / V d / D.
    double expected = 0.0;
    for (const WeightedOperatingPoint& p : table.runs[i].drive_points)
      expected +=
          w4 * 4.0 * tire.footprint.halfLength(p.op.load_n) * tire.footprint.b_m / p.op.speed_mps * p.distance_m;
    expected /= table.runs[i].drive_distance_m;
    EXPECT_NEAR(p1.wear_kg_per_m[i] - p0.wear_kg_per_m[i], expected, 1e-9 * expected) << "segment " << i;
    EXPECT_DOUBLE_EQ(p1.side_force_n[i], p0.side_force_n[i]);  // wear only
  }
}

TEST(RoadTerms, AdhesionWearIsLinearInItsCoefficientAndWearOnly) {
  const RunTable table = driveTable();
  const DiagnosisData data = buildDiagnosisData(table);
  const TireParams tire = roadTire();
  const ExtendedModel base(tire, {}, {}, data);
  const ExtendedModel with(tire, {}, {Term::kAdhesionWear}, data);
  Prediction p0, p1, p2;
  ASSERT_TRUE(base.predict({1.0, 1.0}, &p0));
  ASSERT_TRUE(with.predict({1.0, 1.0, 1e-8}, &p1));
  ASSERT_TRUE(with.predict({1.0, 1.0, 2e-8}, &p2));
  for (std::size_t i = 0; i < table.runs.size(); ++i) {
    const double d1 = p1.wear_kg_per_m[i] - p0.wear_kg_per_m[i], d2 = p2.wear_kg_per_m[i] - p0.wear_kg_per_m[i];
    EXPECT_GT(d1, 0.0);
    EXPECT_NEAR(d2, 2.0 * d1, 1e-9 * d2);
    EXPECT_DOUBLE_EQ(p1.side_force_n[i], p0.side_force_n[i]);
  }
}

TEST(RoadTerms, OnlyForDriveSegments) {
  RunTable steady = driveTable();
  for (RunRecord& r : steady.runs) {
    r.drive_points.clear();
    r.drive_time_s = r.drive_distance_m = 0.0;
  }
  const DiagnosisData data = buildDiagnosisData(steady);
  std::string why;
  EXPECT_FALSE(termApplicable(Term::kContactTimeWear, data, &why));
  EXPECT_NE(why.find("drive segments"), std::string::npos);
  EXPECT_FALSE(termApplicable(Term::kAdhesionWear, data, &why));
  Term t;
  ASSERT_TRUE(parseTerm("contact_time_wear", &t));
  EXPECT_EQ(t, Term::kContactTimeWear);
  EXPECT_EQ(parameterUnit("w4_kg_per_s_m2"), "kg/(s m^2)");
}

TEST(RoadTerms, HoldOutGroupsLeavesWholeGroupsOut) {
  DiagnosisData data = buildDiagnosisData(driveTable());
  holdOutGroups(&data, "brand");
  EXPECT_EQ(data.cv_scheme, "leave one brand out");
  ASSERT_EQ(data.cv_groups.size(), 6u);
  EXPECT_EQ(data.cv_groups[0], data.cv_groups[1]);
  EXPECT_NE(data.cv_groups[1], data.cv_groups[2]);
  EXPECT_EQ(data.cv_groups[4], "brand C");
  try {
    holdOutGroups(&data, "tyre");
    FAIL() << "an unknown covariate must be refused";
  } catch (const DiagnosisError& e) {
    EXPECT_NE(std::string(e.what()).find("'tyre' is not a categorical covariate"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("brand"), std::string::npos);  // names the ones there are
  }
}

namespace {

/// Three brands of two segments each, a calibration test and another, the same drive points for every brand; each
/// brand's measured wear is its own factor times the road tire's prediction.
RunTable brandsOfDifferentAbrasivity(const double factor[3]) {
  RunTable t = driveTable();
  t.text_covariate_names = {"brand", "test"};
  for (std::size_t i = 0; i < t.runs.size(); ++i) {
    t.runs[i].drive_points = t.runs[i % 2].drive_points;
    t.runs[i].op = t.runs[i % 2].op;
    t.runs[i].drive_time_s = t.runs[i % 2].drive_time_s;
    t.runs[i].drive_distance_m = t.runs[i % 2].drive_distance_m;
    t.runs[i].covariates = {t.runs[i].drive_distance_m};
    t.runs[i].text_covariates.push_back(i % 2 == 0 ? "Run-in" : "Urban");
  }
  const DiagnosisData data = buildDiagnosisData(t);
  Prediction p;
  if (!ExtendedModel(roadTire(), {}, {}, data).predict({1.0, 1.0}, &p)) return {};
  for (std::size_t i = 0; i < t.runs.size(); ++i)
    t.runs[i].measured_wear_rate_kg_per_m = factor[i / 2] * p.wear_kg_per_m[i];
  return t;
}

DiagnosisOptions quickOptions() {
  DiagnosisOptions o;
  o.auto_preset = false;
  o.candidates = {Term::kContactTimeWear};
  o.max_terms = 1;
  o.permutations = 99;
  o.detection_power = 0.0;
  o.empirical = false;
  return o;
}

}  // namespace

TEST(RoadTerms, AHeldOutBrandCalibratedOnItsOwnRunInIsPredictedFromItsFactorAlone) {
  // Wear = factor x the model at (w3_scale, mu_scale) = (1, 1): the training brands fit the model's shape exactly,
  // so a held-out brand with its own factor from its Run-in is predicted exactly on its other test, while one
  // scale for all brands mispredicts it by the brands' spread (factor 2 against the others' 0.5 and 1).
  const double factor[3] = {0.5, 1.0, 2.0};
  const RunTable table = brandsOfDifferentAbrasivity(factor);
  ASSERT_EQ(table.runs.size(), 6u);
  DiagnosisData data = buildDiagnosisData(table);
  holdOutGroups(&data, "brand");
  const DiagnosisResult one_scale = diagnose(roadTire(), data, quickOptions());
  calibrateHeldOutGroupsOn(&data, "test", "Run-in");
  EXPECT_EQ(data.cv_scheme, "leave one brand out, each held-out group's wear scale calibrated on its test Run-in");
  EXPECT_EQ(std::vector<char>(data.cv_calibration_run), (std::vector<char>{1, 0, 1, 0, 1, 0}));
  const DiagnosisResult calibrated = diagnose(roadTire(), data, quickOptions());
  const int wear = static_cast<int>(Output::kWear);
  EXPECT_GT(one_scale.base.cv_rmser[wear], 0.4);
  // Exact but for the training fit's convergence: a relative cost change of 1e-10 leaves parameter errors of order
  // its square root, 1e-5, on a valley as flat as mu_scale's here.
  EXPECT_LT(calibrated.base.cv_rmser[wear], 1e-3);
  for (std::size_t i = 0; i < data.runs.size(); ++i)  // a calibration run is fitted, not predicted
    EXPECT_EQ(std::isfinite(calibrated.base.cv_run_loss[i]), i % 2 == 1) << "run " << i;
}

TEST(RoadTerms, CalibratingHeldOutGroupsNamesWhatIsMissing) {
  const double factor[3] = {1.0, 1.0, 1.0};
  DiagnosisData data = buildDiagnosisData(brandsOfDifferentAbrasivity(factor));
  holdOutGroups(&data, "brand");
  auto message = [&](const std::string& covariate, const std::string& level) {
    try {
      calibrateHeldOutGroupsOn(&data, covariate, level);
    } catch (const DiagnosisError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("tyre", "Run-in").find("'tyre' is not a categorical covariate"), std::string::npos);
  EXPECT_NE(message("test", "Motorway").find("'test' has no level 'Motorway'"), std::string::npos);
  holdOutGroups(&data, "test");  // a group of calibration runs only has nothing to predict
  EXPECT_NE(message("test", "Run-in").find("group 'test Run-in' has 3 runs at test 'Run-in' and 0 others"),
            std::string::npos);
}
