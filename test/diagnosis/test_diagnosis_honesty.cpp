// Numerical and statistical honesty of the diagnosis (issue 26, part 0): the solver-error check and its escalation,
// the noise model's selection, and the recordings generated on a finer grid than the diagnosis's.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/noise_model.h"
#include "tread_wear/diagnosis/numerics_check.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/proving/conceal.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

const std::string kGroschParams = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml";

/// A case generated on the converged grid (the `reference` preset).
ConcealCase referenceCase(const TireParams& base, const std::string& effect, const std::string& design,
                          double wear_noise_rsd, double side_force_noise_n, std::uint64_t seed) {
  ConcealSpec spec;
  spec.effect = effect;
  spec.design = design;
  spec.wear_noise_rsd = wear_noise_rsd;
  spec.side_force_noise_n = side_force_noise_n;
  spec.seed = seed;
  spec.model.preset = Preset::kReference;
  return concealEffect(base, spec);
}

/// Deviations drawn with sigma = sqrt(a^2 + (b y)^2) at levels spread over 10..100.
void drawDeviations(double a, double b, int n, std::uint64_t seed, std::vector<double>* e, std::vector<double>* y) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  e->clear();
  y->clear();
  for (int i = 0; i < n; ++i) {
    const double level = 10.0 + 90.0 * i / (n - 1.0);
    y->push_back(level);
    e->push_back(std::sqrt(a * a + b * b * level * level) * normal(rng));
  }
}

}  // namespace

// The generator's own noise model is the independent reference: additive noise selects additive, relative
// selects relative, and the size comes back within the sampling error of 300 values (a std to within about
// +-4% at one standard error; 15% is more than three of them).
TEST(DiagnosisNoiseModel, SelectsTheGeneratorsNoiseModel) {
  std::vector<double> e, y;
  drawDeviations(1.0, 0.0, 300, 1, &e, &y);
  NoiseSelection s = selectNoiseModel(e, y);
  EXPECT_EQ(s.model.kind, NoiseKind::kAdditive);
  EXPECT_NEAR(s.model.additive, 1.0, 0.15);
  EXPECT_DOUBLE_EQ(s.model.relative, 0.0);

  drawDeviations(0.0, 0.05, 300, 2, &e, &y);
  s = selectNoiseModel(e, y);
  EXPECT_EQ(s.model.kind, NoiseKind::kRelative);
  EXPECT_NEAR(s.model.relative, 0.05, 0.05 * 0.15);
  EXPECT_DOUBLE_EQ(s.model.additive, 0.0);

  // Both, equal at y = 50: neither pure model fits the spread over 10..100.
  drawDeviations(1.0, 0.02, 1000, 3, &e, &y);
  s = selectNoiseModel(e, y);
  EXPECT_EQ(s.model.kind, NoiseKind::kCombined);
  EXPECT_LT(s.aicc[2], std::min(s.aicc[0], s.aicc[1]));
}

// Over many samples the selection is right most of the time (not a lucky seed): 40 samples of 36 values each, the
// size of a rig program.
TEST(DiagnosisNoiseModel, SelectionIsRightOnRigSizedSamples) {
  int additive_right = 0, relative_right = 0;
  std::vector<double> e, y;
  for (int k = 0; k < 40; ++k) {
    drawDeviations(1.0, 0.0, 36, 100 + k, &e, &y);
    additive_right += selectNoiseModel(e, y).model.kind == NoiseKind::kAdditive;
    drawDeviations(0.0, 0.05, 36, 200 + k, &e, &y);
    relative_right += selectNoiseModel(e, y).model.kind == NoiseKind::kRelative;
  }
  EXPECT_GE(additive_right, 30);
  EXPECT_GE(relative_right, 30);
}

TEST(DiagnosisNoiseModel, BadInputNamesTheProblem) {
  NoiseKind k = NoiseKind::kRelative;
  EXPECT_FALSE(parseNoiseKind("gaussian", &k));
  EXPECT_EQ(k, NoiseKind::kRelative);
  EXPECT_TRUE(parseNoiseKind("combined", &k));
  EXPECT_EQ(k, NoiseKind::kCombined);
  EXPECT_THROW(selectNoiseModel({1.0, 2.0}, {1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(selectNoiseModel({1.0, 2.0, 3.0}, {1.0, 2.0}), std::invalid_argument);
  std::string error;
  NoiseModel m;
  EXPECT_FALSE(m.validate(&error));
  EXPECT_NE(error.find("additive or relative"), std::string::npos) << error;
  m.additive = -1.0;
  EXPECT_FALSE(m.validate(&error));
  EXPECT_NE(error.find("additive"), std::string::npos) << error;
}

// The check's measure behaves as its definition says: lambda scales as 1/sigma^2, the projection never adds, and
// the reference preset is not checked.
TEST(DiagnosisNumerics, NoncentralityScalesWithTheNoiseAndTheProjectionOnlyRemoves) {
  const TireParams base = loadTireParams(kGroschParams);
  const ConcealCase c = referenceCase(base, "none", "small", 0.05, 1.0, 5);
  const DiagnosisData data = buildDiagnosisData(c.table);
  const std::vector<double> values = {c.answer.parameters.at("w3_scale"), c.answer.parameters.at("mu_scale")};
  NoiseModel noise[kNumOutputs];
  noise[0].additive = 0.1;
  noise[1].relative = 0.005;
  ExtendedModelOptions fast;
  const NumericsCheck tight = checkNumerics(base, data, fast, {}, values, noise, 1.0);
  NoiseModel loose[kNumOutputs] = {noise[0].scaled(10.0), noise[1].scaled(10.0)};
  const NumericsCheck wide = checkNumerics(base, data, fast, {}, values, loose, 1.0);
  ASSERT_TRUE(tight.checked);
  EXPECT_NEAR(wide.noncentrality, tight.noncentrality / 100.0, 1e-9 * tight.noncentrality);
  EXPECT_LE(tight.noncentrality, tight.outputs[0].noncentrality_raw + tight.outputs[1].noncentrality_raw);
  EXPECT_GT(tight.noncentrality, 0.0);
  ExtendedModelOptions reference;
  reference.preset = Preset::kReference;
  EXPECT_FALSE(checkNumerics(base, data, reference, {}, values, noise, 1.0).checked);
}

// Tiny noise over many runs: fast's bias at the rig conditions is many standard errors of the fit, so the diagnosis
// leaves fast and says so; with large noise it keeps fast.
TEST(DiagnosisNumerics, EscalatesWhenTheBiasExceedsTheNoiseOnly) {
  const TireParams base = loadTireParams(kGroschParams);
  DiagnosisOptions opt;
  opt.max_terms = 0;  // the base fit and its check are what this test is about
  opt.permutations = 99;
  opt.detection_power = 0.0;

  const ConcealCase quiet = referenceCase(base, "none", "table2", 0.003, 0.05, 7);
  const DiagnosisResult escalated = diagnose(base, buildDiagnosisData(quiet.table), opt);
  ASSERT_GE(escalated.numerics.size(), 2u);
  EXPECT_FALSE(escalated.numerics.front().passed);
  EXPECT_EQ(escalated.numerics.front().preset, Preset::kFast);
  EXPECT_TRUE(escalated.numerics.back().passed);
  EXPECT_GT(escalated.preset, Preset::kFast);
  EXPECT_NE(escalated.numerics_decision.find("escalated fast"), std::string::npos) << escalated.numerics_decision;

  const ConcealCase noisy = referenceCase(base, "none", "table2", 0.10, 3.0, 7);
  const DiagnosisResult kept = diagnose(base, buildDiagnosisData(noisy.table), opt);
  ASSERT_EQ(kept.numerics.size(), 1u);
  EXPECT_TRUE(kept.numerics.front().passed);
  EXPECT_EQ(kept.preset, Preset::kFast);
  EXPECT_NE(kept.numerics_decision.find("kept"), std::string::npos) << kept.numerics_decision;

  // A given preset is kept, its failed check reported; a limit no preset meets is refused.
  opt.auto_preset = false;
  const DiagnosisResult given = diagnose(base, buildDiagnosisData(quiet.table), opt);
  EXPECT_EQ(given.preset, Preset::kFast);
  EXPECT_NE(given.numerics_warning.find("not small against the measurement noise"), std::string::npos);
  opt.auto_preset = true;
  opt.max_auto_preset = Preset::kStandard;
  opt.numerics_limit = 1e-12;
  try {
    diagnose(base, buildDiagnosisData(noisy.table), opt);
    ADD_FAILURE() << "expected a refusal";
  } catch (const DiagnosisError& e) {
    EXPECT_NE(std::string(e.what()).find("refusing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("standard"), std::string::npos) << e.what();
  }
  opt.numerics_limit = 0.0;
  EXPECT_THROW(diagnose(base, buildDiagnosisData(noisy.table), opt), std::invalid_argument);
}

// The case: additive 1 N side-force noise on small forces (the low-slip design: 3 deg) and an effect that
// touches only the wear, generated on the converged grid: no sensor term is named.
TEST(DiagnosisHonesty, WearOnlyEffectWithAdditiveForceNoiseGetsNoSensorVerdict) {
  const TireParams base = loadTireParams(kGroschParams);
  for (std::uint64_t seed : {21u, 22u}) {
    const ConcealCase c = referenceCase(base, "surface_polishing", "low_slip", 0.05, 1.0, seed);
    DiagnosisOptions opt;
    opt.seed = seed;
    opt.max_terms = 1;
    opt.detection_power = 0.0;
    opt.permutations = 999;
    const DiagnosisResult r = diagnose(base, buildDiagnosisData(c.table), opt);
    for (Term t : r.final_model.terms) EXPECT_TRUE(termInfo(t).physical) << "seed " << seed << ": " << r.explanation;
  }
}
