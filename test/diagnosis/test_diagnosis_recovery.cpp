// Each library term hidden in small generated cases is found and its size recovered; a case without a hidden
// effect gives "none". Noise is set low (wear 1%, side force 0.2 N) so that every term is far above it on the
// 18-run design: these are recovery checks of the machinery, not the success rates at rig noise (those are the
// harness's, docs/diagnosis.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/proving/harness.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

struct Recovery {
  ConcealAnswer answer;
  DiagnosisResult result;
  HarnessOutcome outcome;
};

/// A case of the small 18-run design at low noise (wear RSD 1%, side force 0.2 N unless given), seed 11.
ConcealSpec smallCase(const std::string& effect, double magnitude, double wear_noise_rsd = 0.01,
                      double side_force_noise_n = 0.2) {
  ConcealSpec spec;
  spec.effect = effect;
  spec.magnitude = magnitude;
  spec.design = "small";
  spec.wear_noise_rsd = wear_noise_rsd;
  spec.side_force_noise_n = side_force_noise_n;
  spec.seed = 11;
  return spec;
}

Recovery run(const std::string& effect, double magnitude, double wear_noise_rsd = 0.01, double side_force_noise_n = 0.2,
             int max_terms = 1, double detection_power = 0.0) {
  const ConcealSpec spec = smallCase(effect, magnitude, wear_noise_rsd, side_force_noise_n);
  const TireParams base;
  const ConcealCase c = concealEffect(base, spec);
  const DiagnosisData data = buildDiagnosisData(c.table);
  DiagnosisOptions opt;
  opt.auto_preset = false;  // generated at fast: the machinery, generator = diagnoser
  opt.max_terms = max_terms;  // default 1, single terms: enough to check that the hidden one wins
  opt.permutations = 999;
  opt.detection_power = detection_power;  // off unless asked: the selection is what these tests check
  Recovery r{c.answer, diagnose(base, data, opt), {}};
  r.outcome = scoreCase(HarnessCase{spec, "test"}, c.answer, r.result);
  return r;
}

void expectRecovered(const std::string& effect, double magnitude) {
  const Recovery r = run(effect, magnitude);
  EXPECT_TRUE(r.result.mismatch_found) << effect;
  EXPECT_EQ(r.result.explanation, effect);
  if (r.outcome.parameter_scored) {
    // The criterion: the size of the effect within 25%.
    EXPECT_TRUE(r.outcome.parameter_ok) << effect << ": estimate " << r.outcome.estimate << " truth "
                                        << r.outcome.truth;
  }
  EXPECT_TRUE(r.outcome.improved) << effect << ": held-out RMSER did not improve";
}

const std::string kGroschParams = std::string(TREAD_WEAR_SOURCE_DIR) + "/config/tires/grosch_wheel.yaml";

/// A case of the harness at rig noise (Table 2 design, wear RSD 5%, side force 1 N).
ConcealSpec rigNoiseCase(const std::string& effect, double magnitude, std::uint64_t seed) {
  ConcealSpec spec;
  spec.effect = effect;
  spec.magnitude = magnitude;
  spec.seed = seed;
  return spec;
}

/// A harness case at rig noise, generated with the Grosch wheel and diagnosed as the harness does (the case's
/// seed for the permutations).
struct RigNoiseDiagnosis {
  ConcealSpec spec;
  ConcealCase c;
  DiagnosisOptions options;
  DiagnosisResult result;
};

RigNoiseDiagnosis diagnoseRigNoiseCase(const std::string& effect, double magnitude, std::uint64_t seed,
                                       std::optional<NoiseKind> noise_kind = std::nullopt) {
  const TireParams base = loadTireParams(kGroschParams);
  RigNoiseDiagnosis d;
  d.spec = rigNoiseCase(effect, magnitude, seed);
  d.c = concealEffect(base, d.spec);
  d.options.seed = seed;
  d.options.auto_preset = false;  // generated at fast: the machinery, generator = diagnoser
  for (std::optional<NoiseKind>& kind : d.options.noise_kind) kind = noise_kind;
  d.options.detection_power = 0.0;
  d.result = diagnose(base, buildDiagnosisData(d.c.table), d.options);
  return d;
}

const FittedModel* findTried(const DiagnosisResult& r, const std::string& label) {
  for (const FittedModel& f : r.tried)
    if (f.label == label) return &f;
  return nullptr;
}

}  // namespace

TEST(DiagnosisRecovery, NoEffectGivesNone) {
  const Recovery r = run("none", std::nan(""), 0.01, 0.2, 1, 0.8);
  EXPECT_FALSE(r.result.mismatch_found);
  EXPECT_EQ(r.result.explanation, "none");
  EXPECT_TRUE(r.result.final_model.terms.empty());
  // The base fit recovers the hidden level parameters to within the noise (1% wear, 0.2 N side force).
  EXPECT_NEAR(fittedValue(r.result.base, "w3_scale") / r.answer.parameters.at("w3_scale"), 1.0, 0.02);
  EXPECT_NEAR(fittedValue(r.result.base, "mu_scale") / r.answer.parameters.at("mu_scale"), 1.0, 0.01);
  // What the `none` rules out: a limit for every term of the library, at the noise left (wear RSD 1%: 18 values,
  // so within about +-35% at 95%).
  EXPECT_NEAR(r.result.wear_noise_rsd, 0.01, 0.0035);
  ASSERT_EQ(r.result.detection_limits.size(), termLibrary().size());
  for (const DetectionLimit& l : r.result.detection_limits) {
    if (l.term == "turn_slip_orientation") {
      EXPECT_GT(l.switch_power, 0.8);
    } else if (l.term == "contact_time_wear" || l.term == "adhesion_wear") {
      EXPECT_EQ(l.note.rfind("not applicable", 0), 0u) << l.term << ": road terms, drive segments only";
    } else if (l.term != "load_fluctuation") {
      EXPECT_TRUE(std::isfinite(l.above) || std::isfinite(l.below)) << l.term;
    }
  }
}

// Recordings without noise, e.g. a simulation checked against the same model: the fit reproduces them to
// round-off, and round-off is neither a mismatch nor something a second term explains.
TEST(DiagnosisRecovery, NoiseFreeRecordings) {
  const Recovery control = run("none", std::nan(""), 0.0, 0.0, 2);
  EXPECT_EQ(control.result.explanation, "none");
  EXPECT_TRUE(control.result.tried.empty()) << "no term is fitted to round-off";
  EXPECT_TRUE(control.result.located_before.empty());
  ASSERT_EQ(control.result.not_located.size(), 2u) << "both outputs: nothing to locate";
  EXPECT_NE(control.result.not_located[0].find("numerical resolution"), std::string::npos);
  EXPECT_NEAR(fittedValue(control.result.base, "mu_scale") / control.answer.parameters.at("mu_scale"), 1.0, 1e-6);

  const Recovery offset = run("sensor_offset", 4.0, 0.0, 0.0, 2);
  EXPECT_EQ(offset.result.explanation, "sensor_offset") << "the exact term alone, no second term";
  EXPECT_NEAR(fittedValue(offset.result.final_model, "side_force_offset_n"), 4.0, 1e-4);
  EXPECT_TRUE(offset.result.not_located.empty()) << "without the offset, both outputs are off";
  EXPECT_EQ(offset.result.not_located_after.size(), 2u) << "the offset model reproduces both outputs";
}

// A term named twice among the candidates is fitted once and counts once in the Bonferroni threshold.
TEST(DiagnosisRecovery, RepeatedCandidateCountsOnce) {
  const TireParams base;
  const ConcealCase c = concealEffect(base, smallCase("sensor_offset", 4.0));
  DiagnosisOptions opt;
  opt.auto_preset = false;  // generated at fast: the machinery, generator = diagnoser
  opt.max_terms = 1;
  opt.permutations = 999;
  opt.candidates = {Term::kSensorOffset, Term::kSensorOffset, Term::kSensorGain};
  const DiagnosisResult r = diagnose(base, buildDiagnosisData(c.table), opt);
  EXPECT_EQ(r.tried.size(), 2u);
  ASSERT_FALSE(r.log.empty());
  EXPECT_NE(r.log[0].find("2 terms tried"), std::string::npos) << r.log[0];
  EXPECT_EQ(r.explanation, "sensor_offset");
}

TEST(DiagnosisRecovery, ThermalWear) { expectRecovered("thermal_wear", 30.0); }
TEST(DiagnosisRecovery, ThermalFriction) { expectRecovered("thermal_friction", 0.005); }
TEST(DiagnosisRecovery, SurfacePolishing) { expectRecovered("surface_polishing", 0.6); }
TEST(DiagnosisRecovery, LateralCompliance) { expectRecovered("lateral_compliance", 3e-4); }
TEST(DiagnosisRecovery, PressureFriction) { expectRecovered("pressure_friction", 0.45); }
TEST(DiagnosisRecovery, LoadFluctuation) { expectRecovered("load_fluctuation", 0.4); }
TEST(DiagnosisRecovery, TurnSlipOrientation) { expectRecovered("turn_slip_orientation", std::nan("")); }
TEST(DiagnosisRecovery, SensorGain) { expectRecovered("sensor_gain", 1.08); }
TEST(DiagnosisRecovery, SensorOffset) { expectRecovered("sensor_offset", 4.0); }

// Wear that follows a recorded covariate no library term knows (here humidity) is a mismatch the library cannot
// explain: the verdict is "unexplained" and the covariate is named.
TEST(DiagnosisRecovery, EffectOutsideTheLibraryIsUnexplained) {
  const TireParams base;
  ConcealCase c = concealEffect(base, smallCase("none", std::nan("")));
  std::mt19937 draws(7);
  std::uniform_real_distribution<double> humidity(0.2, 0.8);
  c.table.covariate_names.push_back("humidity");
  for (RunRecord& run : c.table.runs) {
    const double h = humidity(draws);
    run.covariates.push_back(h);
    run.measured_wear_rate_kg_per_m *= 1.0 + 0.8 * (h - 0.5);  // +-24% of wear, 24x the noise
  }
  DiagnosisOptions opt;
  opt.auto_preset = false;  // generated at fast: the machinery, generator = diagnoser
  opt.max_terms = 1;  // default 9999 permutations: 999 cannot pass the Holm correction over every covariate
  const DiagnosisResult r = diagnose(base, buildDiagnosisData(c.table), opt);
  EXPECT_TRUE(r.mismatch_found);
  EXPECT_EQ(r.explanation, "unexplained");
  EXPECT_NE(std::find(r.unexplained_covariates.begin(), r.unexplained_covariates.end(), "humidity"),
            r.unexplained_covariates.end())
      << "the residual follows humidity";
}

TEST(DiagnosisRecovery, ChanceSecondTermIsNotAccepted) {
  // Harness case surface_polishing large, seed 1046: by chance the 50 N runs read ~1.5 N high, and a side-force
  // term (pressure_friction) lowers the held-out error after the polishing term (score 0.97 vs 1.11), but only on
  // those few runs: the paired rank test over the runs does not reach alpha_select, so the pair is refused.
  const RigNoiseDiagnosis d = diagnoseRigNoiseCase("surface_polishing", 0.8, 1046);
  const DiagnosisResult& r = d.result;
  EXPECT_EQ(r.explanation, "surface_polishing");
  const FittedModel* pair = findTried(r, "surface_polishing+pressure_friction");
  const FittedModel* single = findTried(r, "surface_polishing");
  ASSERT_NE(pair, nullptr);
  ASSERT_NE(single, nullptr);
  EXPECT_LT(pair->cv_score, r.final_model.cv_score) << "lower held out, the old acceptance rule";
  EXPECT_GE(pair->p_held_out, d.options.alpha_select);
}

// Harness case sensor_gain large (1.10), seed 5119: with mu_scale free, a gain and an offset of the side-force
// transducer fit the Table 2 program almost equally well (Fy is proportional to mu at the large slip angles, so
// only the low-slip runs tell them apart). Whichever is chosen, the other is reported as a close alternative, and
// scoring counts the hidden term as named though not as the explanation.
// Under relative weights for both outputs (the weighting of that harness run; with the additive side-force noise
// model that these repeats select, the offset is ahead by AICc 2.4 and no longer a close alternative).
TEST(DiagnosisRecovery, IndistinguishableTermIsReportedAsCloseAlternative) {
  const RigNoiseDiagnosis d = diagnoseRigNoiseCase("sensor_gain", 1.10, 5119, NoiseKind::kRelative);
  const DiagnosisResult& r = d.result;
  ASSERT_TRUE(r.explanation == "sensor_gain" || r.explanation == "sensor_offset") << r.explanation;
  const std::string other = r.explanation == "sensor_gain" ? "sensor_offset" : "sensor_gain";
  ASSERT_EQ(r.close_alternatives.size(), 1u);
  EXPECT_EQ(r.close_alternatives[0].model, other);
  EXPECT_EQ(r.close_alternatives[0].instead_of, r.explanation);
  const FittedModel* alternative = findTried(r, other);
  const FittedModel* chosen = findTried(r, r.explanation);
  ASSERT_NE(alternative, nullptr);
  ASSERT_NE(chosen, nullptr);
  EXPECT_DOUBLE_EQ(r.close_alternatives[0].delta_aicc, alternative->aicc - chosen->aicc);
  EXPECT_LT(std::abs(r.close_alternatives[0].delta_aicc), d.options.min_aicc_drop);
  const HarnessOutcome o = scoreCase(HarnessCase{d.spec, "large"}, d.c.answer, r);
  EXPECT_TRUE(o.named);
  EXPECT_EQ(o.right, r.explanation == "sensor_gain");
}

TEST(DiagnosisRecovery, GenuinePairIsAccepted) {
  // Two hidden terms at rig noise: thermal_friction (k_T 0.006 / K) and surface_polishing (0.8 / km). The second
  // term improves the held-out error on most runs, far below alpha_select.
  const TireParams base = loadTireParams(kGroschParams);
  const ConcealSpec spec = rigNoiseCase("thermal_friction", 0.006, 5001);
  ConcealCase c = concealEffect(base, spec);
  const DiagnosisData plain = buildDiagnosisData(c.table);
  ExtendedModel truth(base, spec.model, {Term::kThermalFriction, Term::kSurfacePolishing}, plain);
  std::vector<double> values;
  for (const FitParameter& p : truth.parameters()) {
    const auto it = c.answer.parameters.find(p.name);
    values.push_back(it != c.answer.parameters.end() ? it->second : p.initial);
  }
  values[truth.parameterOffset(Term::kSurfacePolishing)] = 0.8;
  Prediction pred;
  ASSERT_TRUE(truth.predict(values, &pred));
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::size_t i = 0; i < c.table.runs.size(); ++i) {
    c.table.runs[i].measured_side_force_n = pred.side_force_n[i] + spec.side_force_noise_n * noise(rng);
    c.table.runs[i].measured_wear_rate_kg_per_m = pred.wear_kg_per_m[i] * (1.0 + spec.wear_noise_rsd * noise(rng));
  }
  DiagnosisOptions opt;
  opt.auto_preset = false;  // generated at fast: the machinery, generator = diagnoser
  opt.seed = 1;
  const DiagnosisResult r = diagnose(base, buildDiagnosisData(c.table), opt);
  EXPECT_EQ(r.explanation, "thermal_friction+surface_polishing");
  const FittedModel* pair = findTried(r, "thermal_friction+surface_polishing");
  ASSERT_NE(pair, nullptr);
  EXPECT_LT(pair->p_held_out, 1e-4);
  EXPECT_NEAR(fittedValue(r.final_model, "polishing_rate_per_km"), 0.8, 0.2);
  EXPECT_NEAR(fittedValue(r.final_model, "k_t_per_k"), 0.006, 0.0015);
}
