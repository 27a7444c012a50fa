// Eq 26 reference wear models (reference_models.h) against hand calculations and manufactured fits.
#include <gtest/gtest.h>

#include <cmath>

#include "tread_wear/fitting/reference_models.h"

namespace tread_wear {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(ReferenceWearLaw, PaperMpMatchesHandCalculation) {
  // Table 5 M_P (w1 = w2 = 1.36, w3 = 2.32e-2 mg/s, w4 = 9.53e-2 mg/s) at the Table 3 benchmark row
  // (v0 = 2 m/s, alpha = 10 deg, Fy = 48.78 N), by hand:
  //   (9.53e-2 + 2.32e-2 * 48.78^1.36 * (2 sin 10 deg)^1.36) / 2 = 0.591926 mg/m.
  const ReferenceWearLaw law = paperReferenceLaw(ReferenceModelKind::kP);
  const double wr = law.wearRate_kg_per_m(48.78, 2.0, -10.0 * kDeg);
  constexpr double kTol = 1e-6;  // relative; the hand value is given to 6 digits
  EXPECT_NEAR(wr / 0.591926e-6, 1.0, kTol);
  EXPECT_DOUBLE_EQ(law.w1, law.w2);
}

TEST(ReferenceWearLaw, PaperMepMatchesHandCalculation) {
  // Table 5 M_EP at v0 = 2 m/s, alpha = 15 deg, Fy = 62.59 N:
  //   (0.11e-2 + 7.22e-2 * 62.59^1.11 * (2 sin 15 deg)^1.48) / 2 = 1.344511 mg/m.
  const ReferenceWearLaw law = paperReferenceLaw(ReferenceModelKind::kEP);
  EXPECT_NEAR(law.wearRate_kg_per_m(62.59, 2.0, 15.0 * kDeg) / 1.344511e-6, 1.0, 1e-6);
}

TEST(ReferenceWearLaw, OffsetOnlyAndTemperatureFactor) {
  // Without slip the law is w4 / v0; Eq 25 at T = T0 + sigma multiplies w3 by exp(1/2).
  ReferenceWearLaw law;
  law.w4_kg_per_s = 2e-9;
  EXPECT_DOUBLE_EQ(law.wearRate_kg_per_m(10.0, 4.0, 0.0), 0.5e-9);
  law.w4_kg_per_s = 0.0;
  law.w1 = 1.0;
  law.w2 = 1.0;
  law.w3_kg_per_s = 1e-8;
  const double base = law.wearRate_kg_per_m(10.0, 1.0, M_PI / 6.0);  // 1e-8 * 10 * 0.5 / 1
  EXPECT_NEAR(base, 5e-8, 1e-20);
  law.temperature_enabled = true;
  law.t0_c = 40.0;
  law.sigma_t_c = 10.0;
  EXPECT_NEAR(law.wearRate_kg_per_m(10.0, 1.0, M_PI / 6.0, 50.0), 5e-8 * std::exp(0.5), 1e-20);
  EXPECT_NEAR(law.wearRate_kg_per_m(10.0, 1.0, M_PI / 6.0), 5e-8, 1e-20);  // unknown temperature: no factor
  std::string err;
  law.sigma_t_c = 0.0;
  EXPECT_FALSE(law.validate(&err));
  EXPECT_NE(err.find("sigma_t_c"), std::string::npos);
}

RunTable syntheticRuns(const ReferenceWearLaw& truth) {
  // Table 3 conditions and side forces, wear generated from `truth`.
  const double rows[9][4] = {{1, 10, 75, 50.60}, {2, 10, 75, 50.48}, {3, 10, 75, 52.50},
                             {2, 5, 75, 21.79},  {2, 10, 75, 48.78}, {2, 15, 75, 62.59},
                             {2, 10, 50, 39.09}, {2, 10, 75, 49.30}, {2, 10, 100, 57.99}};
  RunTable t;
  for (const auto& row : rows) {
    RunRecord r;
    r.op.speed_mps = row[0];
    r.op.slip_angle_rad = -row[1] * kDeg;
    r.op.load_n = row[2];
    r.measured_side_force_n = row[3];
    r.condition_id = "v" + std::to_string(row[0]) + "a" + std::to_string(row[1]) + "f" + std::to_string(row[2]);
    r.measured_wear_rate_kg_per_m = truth.wearRate_kg_per_m(row[3], row[0], r.op.slip_angle_rad);
    t.runs.push_back(r);
  }
  return t;
}

TEST(ReferenceFit, RecoversManufacturedMep) {
  ReferenceWearLaw truth;
  truth.w1 = 1.2;
  truth.w2 = 1.6;
  truth.w3_kg_per_s = 5e-8;
  truth.w4_kg_per_s = 1e-8;
  const RunTable runs = syntheticRuns(truth);
  const ReferenceFit fit = fitReferenceModel(ReferenceModelKind::kEP, runs, paperReferenceLaw(ReferenceModelKind::kEP));
  ASSERT_TRUE(fit.summary.usable) << fit.summary.message;
  // Noise-free data, 4 parameters from 7 distinct conditions: limited by solver tolerances only.
  constexpr double kTol = 1e-4;
  EXPECT_NEAR(fit.law.w1, 1.2, kTol);
  EXPECT_NEAR(fit.law.w2, 1.6, kTol);
  EXPECT_NEAR(fit.law.w3_kg_per_s / 5e-8, 1.0, kTol);
  EXPECT_NEAR(fit.law.w4_kg_per_s / 1e-8, 1.0, kTol);
  EXPECT_LT(fit.rmser, 1e-5);
  EXPECT_LT(fit.cv_rmser, 1e-4);  // the true law predicts every held-out condition too
  ASSERT_EQ(fit.cv_predicted_kg_per_m.size(), 9u);
}

TEST(ReferenceFit, MpTiesTheExponents) {
  ReferenceWearLaw truth;
  truth.w1 = truth.w2 = 1.4;
  truth.w3_kg_per_s = 2e-8;
  truth.w4_kg_per_s = 5e-8;
  const ReferenceFit fit =
      fitReferenceModel(ReferenceModelKind::kP, syntheticRuns(truth), paperReferenceLaw(ReferenceModelKind::kP));
  ASSERT_TRUE(fit.summary.usable);
  EXPECT_EQ(fit.summary.parameters.size(), 3u);  // w1 (= w2), w3, w4
  EXPECT_NEAR(fit.law.w1, 1.4, 1e-4);
  EXPECT_DOUBLE_EQ(fit.law.w1, fit.law.w2);
}

TEST(ReferenceFit, TemperatureModelsNeedTemperatures) {
  const RunTable runs = syntheticRuns(paperReferenceLaw(ReferenceModelKind::kEP));
  EXPECT_THROW(fitReferenceModel(ReferenceModelKind::kEPT, runs, paperReferenceLaw(ReferenceModelKind::kEPT)),
               std::invalid_argument);
  RunTable empty;
  EXPECT_THROW(fitReferenceModel(ReferenceModelKind::kP, empty, {}), std::invalid_argument);
}

}  // namespace
}  // namespace tread_wear
