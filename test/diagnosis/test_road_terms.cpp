// The road wear terms of the library (extensions.h): contact_time_wear adds w4 4ab/V per distance, checked against
// that closed form summed over each segment's own points (not the cells the model bins them into); adhesion_wear
// adds a wear linear in its coefficient; both apply to drive segments only. And the cross-validation by whole
// groups of a recorded covariate (data.h, holdOutGroups).
#include <gtest/gtest.h>

#include <cmath>

#include "tread_wear/diagnosis/data.h"
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
