// Empirical terms for what the library lacks (empirical.h): a wear dependence on humidity concealed with the
// example mechanism and diagnosed without it is `unexplained` with an empirical term in humidity_percent of the
// right sign that lowers the held-out wear error, reported in diagnosis.json and report.md; a per-cycle batch
// effect gets offsets per cycle; a control is `none`
// without one; the linear term's estimate agrees with a closed-form least-squares slope on the same data; a
// covariate without variance gets no family and a reason.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/empirical.h"
#include "tread_wear/diagnosis/user_mechanisms.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/report/diagnosis_report.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
const std::string kParams = kSource + "/config/tires/grosch_wheel.yaml";
const std::string kExample = kSource + "/config/mechanisms/example.yaml";
constexpr int kWear = static_cast<int>(Output::kWear);

/// Recordings with the example file's humidity mechanism concealed (k_h per % RH; 0 = a control); the file is
/// unloaded again before they are returned, so the diagnosis's library lacks the mechanism.
RunTable humidityCase(double k_h_per_percent, std::uint64_t seed) {
  const MechanismsInUse mechanisms(kExample);
  ConcealSpec spec;
  spec.effect = k_h_per_percent == 0.0 ? "none" : "humidity_abrasion";
  if (k_h_per_percent != 0.0) spec.magnitude = k_h_per_percent;
  spec.design = "small";
  spec.seed = seed;
  return concealEffect(loadTireParams(kParams), spec).table;
}

DiagnosisOptions options() {
  DiagnosisOptions opt;  // the default 9999 permutations: Holm over ~30 tests needs p below ~3e-4
  opt.detection_power = 0.0;
  return opt;
}

}  // namespace

TEST(EmpiricalTerms, ConcealedHumidityGetsAnEmpiricalTermThatImprovesTheHeldOutError) {
  const DiagnosisData data = buildDiagnosisData(humidityCase(-0.015, 11));
  Term unloaded;
  ASSERT_FALSE(parseTerm("humidity_abrasion", &unloaded));  // the library lacks the mechanism
  const DiagnosisResult r = diagnose(loadTireParams(kParams), data, options());
  EXPECT_EQ(r.explanation, "unexplained");  // the physics stays unexplained
  EXPECT_TRUE(r.final_model.terms.empty());
  ASSERT_TRUE(r.empirical.attempted);
  EXPECT_EQ(r.empirical.covariate, "humidity_percent");
  ASSERT_EQ(r.empirical.terms.size(), 1u) << r.empirical.reason;
  const EmpiricalTerm& t = r.empirical.terms[0];
  EXPECT_EQ(t.output, Output::kWear);
  EXPECT_LT(t.parameters.at(0).value, 0.0);  // wear falls with humidity (k_h < 0), whatever the form
  EXPECT_LT(t.cv_rmser_after, t.cv_rmser_before);
  EXPECT_LT(t.p_value, 0.01);

  const nlohmann::json j = nlohmann::json::parse(diagnosisJson(r, data));
  EXPECT_EQ(j["explanation"], "unexplained");
  EXPECT_TRUE(j["explanation_terms"].empty());
  ASSERT_EQ(j["empirical_terms"].size(), 1u);
  EXPECT_EQ(j["empirical_terms"][0]["covariate"], "humidity_percent");
  EXPECT_EQ(j["empirical_terms"][0]["physical"], false);
  EXPECT_EQ(j["plot_covariates"]["wear"], "humidity_percent");
  const std::string csv = residualsCsv(r, data);
  EXPECT_NE(csv.substr(0, csv.find('\n')).find(",residual_wear_empirical"), std::string::npos);
  const std::string md = diagnosisMarkdown(r, data, "case", {});
  EXPECT_NE(md.find("empirical model (not physics): wear x"), std::string::npos);
  EXPECT_NE(md.find("no library mechanism matches"), std::string::npos);
  EXPECT_NE(md.find("## Empirical terms (not physics)"), std::string::npos);
}

// A per-cycle batch effect (config/mechanisms/out_of_library.yaml: wear x (1 + b sin(2.4 cycle_id + 1)), b = 0.2,
// so cycle 3 reads 19% high and cycle 4 18% low against cycle 1's 5% low) gets offsets per cycle, whose held-out
// error is leave one run out: leave one cycle out could not predict a held-out cycle's offset. Without a recorded
// per-cycle covariate: the generator's ambient_c (one value per cycle) is dropped, since a covariate term in it is
// tried first and, judged by whole cycles left out, may describe six cycle levels with two parameters (at this seed
// a quadratic in ambient_c does; PerCycleRecordedCovariateWinsOverCycleOffsets is that case on purpose).
TEST(EmpiricalTerms, ConcealedBatchEffectGetsCycleOffsets) {
  RunTable table;
  {
    const MechanismsInUse mechanisms(kSource + "/config/mechanisms/out_of_library.yaml");
    ConcealSpec spec;
    spec.effect = "cycle_batch";
    spec.magnitude = 0.2;
    spec.seed = 1078;
    table = concealEffect(loadTireParams(kParams), spec).table;
  }
  const auto ambient = std::find(table.covariate_names.begin(), table.covariate_names.end(), "ambient_c");
  ASSERT_NE(ambient, table.covariate_names.end());
  const auto column = ambient - table.covariate_names.begin();
  table.covariate_names.erase(ambient);
  for (RunRecord& r : table.runs) r.covariates.erase(r.covariates.begin() + column);
  const DiagnosisData data = buildDiagnosisData(table);
  const DiagnosisResult r = diagnose(loadTireParams(kParams), data, options());
  EXPECT_EQ(r.explanation, "unexplained");
  ASSERT_EQ(r.empirical.terms.size(), 1u) << r.empirical.reason;
  const EmpiricalTerm& t = r.empirical.terms[0];
  EXPECT_EQ(t.name, "empirical_group_offsets_cycle_id");
  EXPECT_EQ(t.cv_scheme, "leave one run out");
  EXPECT_LT(t.cv_rmser_after, t.cv_rmser_before);
  ASSERT_EQ(t.parameters.size(), 5u);     // cycles 2..6 against cycle 1
  EXPECT_GT(t.parameters[1].value, 0.0);  // cycle 3 above cycle 1
  EXPECT_LT(t.parameters[2].value, 0.0);  // cycle 4 below
}

// A recorded covariate constant within each test cycle (the generator's ambient_c, one value per cycle) that
// explains the wear: wear x exp(k (ambient_c - 23 degC)), k = -0.06 /K (about +-18% over the cycles' +-3 degC).
// The located effects include cycle_id as well; one offset per cycle (5 parameters) cannot predict a cycle held out
// whole, while the covariate's one parameter can: the covariate's term must win, judged leaving whole cycles out.
TEST(EmpiricalTerms, PerCycleRecordedCovariateWinsOverCycleOffsets) {
  ConcealSpec spec;  // a control on the Table 2 design (six cycles), then the covariate's effect on the wear
  spec.seed = 4242;
  RunTable table = concealEffect(loadTireParams(kParams), spec).table;
  const int ambient =
      static_cast<int>(std::find(table.covariate_names.begin(), table.covariate_names.end(), "ambient_c") -
                       table.covariate_names.begin());
  ASSERT_LT(ambient, static_cast<int>(table.covariate_names.size()));
  std::map<int, std::set<double>> per_cycle;
  for (RunRecord& r : table.runs) {
    per_cycle[r.cycle_id].insert(r.covariates[ambient]);
    r.measured_wear_rate_kg_per_m *= std::exp(-0.06 * (r.covariates[ambient] - 23.0));
  }
  ASSERT_EQ(per_cycle.size(), 6u);
  for (const auto& [cycle, values] : per_cycle) ASSERT_EQ(values.size(), 1u) << "cycle " << cycle;
  const DiagnosisData data = buildDiagnosisData(table);
  ASSERT_EQ(data.cv_scheme, "leave one cycle out");
  const DiagnosisResult r = diagnose(loadTireParams(kParams), data, options());
  EXPECT_EQ(r.explanation, "unexplained");
  ASSERT_EQ(r.empirical.terms.size(), 1u) << r.empirical.reason;
  const EmpiricalTerm& t = r.empirical.terms[0];
  EXPECT_EQ(t.covariate, "ambient_c");
  EXPECT_NE(t.form, "group_offsets");
  EXPECT_EQ(t.cv_scheme, "leave one cycle out");  // judged by whole cycles left out
  EXPECT_LT(t.parameters.at(0).value, 0.0);
  EXPECT_LT(t.cv_rmser_after, t.cv_rmser_before);
}

TEST(EmpiricalTerms, ControlIsNoneWithoutEmpiricalTerm) {
  const DiagnosisData data = buildDiagnosisData(humidityCase(0.0, 12));
  const DiagnosisResult r = diagnose(loadTireParams(kParams), data, options());
  EXPECT_EQ(r.explanation, "none");
  EXPECT_FALSE(r.empirical.attempted);
  EXPECT_TRUE(r.empirical.terms.empty());
  EXPECT_TRUE(nlohmann::json::parse(diagnosisJson(r, data))["empirical_terms"].empty());
}

// The linear term alone, fitted by the diagnosis's selection, against the closed form: with the brush outputs at the
// base solution, the wear runs' relative errors q_i c (1 + b dx_i) - 1 (q_i = predicted/measured, c the wear level)
// are linear in A = c and B = c b, so b = B / A from two normal equations. Equal weights within an output, as the
// diagnosis's. The two differ only through what the closed form holds fixed (mu_scale, w4's share of the wear).
TEST(EmpiricalTerms, LinearSlopeMatchesClosedFormLeastSquares) {
  const DiagnosisData data = buildDiagnosisData(humidityCase(-0.01, 13));
  std::string why;
  std::vector<TermInfo> family = empiricalFamily(data, "humidity_percent", Output::kWear, &why);
  ASSERT_GE(family.size(), 3u) << why;
  ASSERT_EQ(family[0].name, "empirical_linear_humidity_percent");
  std::vector<TermInfo> library = termLibrary();
  family[0].term = static_cast<Term>(library.size());
  library.push_back(family[0]);
  const std::vector<TermInfo>* previous = setThreadLibrary(&library);
  DiagnosisOptions opt = options();
  opt.candidates = {family[0].term};
  opt.max_terms = 1;
  opt.empirical = false;
  const DiagnosisResult r = diagnose(loadTireParams(kParams), data, opt);
  setThreadLibrary(previous);
  ASSERT_EQ(r.final_model.label, "empirical_linear_humidity_percent");
  double se = 0.0;
  const double b = fittedValue(r.final_model, "emp_lin_b", &se);
  ASSERT_TRUE(std::isfinite(se) && se > 0.0);

  std::vector<double> x;
  for (const Covariate& c : data.covariates)
    if (c.name == "humidity_percent") x = c.values;
  double m = 0.0;
  for (double v : x) m += v / x.size();
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    const double meas = data.runs[i].measured[kWear];
    if (!std::isfinite(meas)) continue;
    const double q = r.base.prediction.wear_kg_per_m[i] / meas;
    const Eigen::Vector2d row(q, q * (x[i] - m));
    normal += row * row.transpose();
    rhs += row;
  }
  const Eigen::Vector2d ab = normal.ldlt().solve(rhs);
  const double b_reference = ab(1) / ab(0);
  EXPECT_LT(b_reference, 0.0);
  EXPECT_NEAR(b, b_reference, se) << "closed form " << b_reference << ", fitted " << b << " +- " << se;
}

TEST(EmpiricalTerms, CovariateWithoutVarianceGetsNoFamilyAndAReason) {
  RunTable table = humidityCase(0.0, 14);
  std::size_t column = 0;
  while (table.covariate_names.at(column) != "humidity_percent") ++column;
  for (RunRecord& run : table.runs) run.covariates[column] = 45.0;
  DiagnosisData data = buildDiagnosisData(table);
  std::string why;
  // A constant recorded column is not offered as a covariate at all ...
  EXPECT_TRUE(empiricalFamily(data, "humidity_percent", Output::kWear, &why).empty());
  EXPECT_NE(why.find("without variance is not one"), std::string::npos) << why;
  // ... and one given by hand gets the reason.
  data.covariates.push_back({"humidity_percent", "recorded", false, std::vector<double>(data.runs.size(), 45.0), {}});
  EXPECT_TRUE(empiricalFamily(data, "humidity_percent", Output::kWear, &why).empty());
  EXPECT_NE(why.find("no variance on the runs (every value 45)"), std::string::npos) << why;
  EXPECT_TRUE(empiricalFamily(data, "condition_id", Output::kWear, &why).empty());
  EXPECT_NE(why.find("categorical and not numbered"), std::string::npos) << why;
  EXPECT_TRUE(empiricalFamily(data, "abs_slip_angle_deg", Output::kWear, &why).empty());
  EXPECT_NE(why.find("not a variable an expression can read"), std::string::npos) << why;
  // A sequence covariate gets the saturating step besides; every term is the model at its no-effect values.
  const std::vector<TermInfo> sequence = empiricalFamily(data, "run_order", Output::kWear, &why);
  ASSERT_EQ(sequence.size(), 4u) << why;
  EXPECT_EQ(sequence[3].name, "empirical_saturating_step_run_order");
  Prediction model;
  for (const DiagnosisRun& run : data.runs) {
    model.side_force_n.push_back(run.measured[0]);
    model.wear_kg_per_m.push_back(run.measured[kWear]);
  }
  for (const TermInfo& t : sequence) EXPECT_NO_THROW(checkNoEffect(t, data, model)) << t.name;
  // The cycles get one offset each but the first (the small design has three).
  const std::vector<TermInfo> groups = empiricalFamily(data, "cycle_id", Output::kWear, &why);
  ASSERT_EQ(groups.size(), 1u) << why;
  EXPECT_EQ(groups[0].name, "empirical_group_offsets_cycle_id");
  EXPECT_EQ(groups[0].parameters.size(), 2u);
  EXPECT_NO_THROW(checkNoEffect(groups[0], data, model));
}
