// User-defined mechanisms (docs/diagnosis.md, "User-defined mechanisms"): the example file loads; every malformed
// file gets an error that names its line; a mechanism at its no-effect values is the model; a concealed user
// mechanism is selected and its size recovered through the tools; a control stays `none` with the file loaded; a
// mechanism that restates a built-in term fits, cross-validates and has detection limits as the built-in does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/temp_file.h"
#include "tread_wear/cli/diagnosis_cli.h"
#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/user_mechanisms.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/proving/conceal.h"
#include "tread_wear/proving/harness.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
const std::string kParams = kSource + "/config/tires/grosch_wheel.yaml";
const std::string kExample = kSource + "/config/mechanisms/example.yaml";

/// A mechanisms document with one mechanism whose fields are given (each a line of the entry, in this order).
// clang-format off
std::string document(const std::string& expression, const std::string& parameter_line,
                     const std::string& affects = "[wear]", const std::string& name = "my_term") {
  return "mechanisms:\n"                                  // 1
         "  - name: " + name + "\n"                       // 2
         "    statement: a one-line physical statement\n"  // 3
         "    parameters:\n"                              // 4
         "      - " + parameter_line + "\n"               // 5
         "    affects: " + affects + "\n"                 // 6
         "    covariates: [humidity_percent]\n"           // 7
         "    expression: " + expression + "\n";          // 8
}
// clang-format on
const std::string kParameter = "{name: k, unit: 1/%, lower: -0.1, upper: 0.1, no_effect: 0}";

/// The error that compiling the document gives ("" for none).
std::string compileError(const std::string& text) {
  try {
    compileMechanisms(parseMechanismFile(text, "m.yaml"));
  } catch (const MechanismFileError& e) {
    return e.what();
  }
  return "";
}

ConcealSpec spec(const std::string& effect, double magnitude, const std::string& design, std::uint64_t seed) {
  ConcealSpec s;
  s.effect = effect;
  s.magnitude = magnitude;
  s.design = design;
  s.seed = seed;
  return s;
}

DiagnosisOptions quickOptions() {
  DiagnosisOptions opt;
  opt.permutations = 999;
  opt.detection_power = 0.0;
  return opt;
}

struct CliResult {
  int code;
  std::string out, err;
};

CliResult runCli(const std::function<int(int, const char* const[], std::ostream&, std::ostream&)>& cli,
                 std::vector<std::string> args) {
  args.insert(args.begin(), "tool");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int code = cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {code, out.str(), err.str()};
}

CliResult diagnoseCli(std::vector<std::string> args) {
  return runCli([](int argc, const char* const argv[], std::ostream& out,
                   std::ostream& err) { return runDiagnoseCli(argc, argv, {}, "", out, err); },
                std::move(args));
}

}  // namespace

TEST(UserMechanisms, ExampleFileLoadsForTheLifetimeOfItsScope) {
  Term t;
  ASSERT_FALSE(parseTerm("humidity_abrasion", &t));
  {
    const MechanismsInUse mechanisms(kExample);
    ASSERT_TRUE(parseTerm("humidity_abrasion", &t));
    EXPECT_EQ(t, Term::kFirstUser);
    const TermInfo& info = termInfo(t);
    EXPECT_TRUE(info.user != nullptr);
    EXPECT_FALSE(info.affects[static_cast<int>(Output::kSideForce)]);
    EXPECT_TRUE(info.affects[static_cast<int>(Output::kWear)]);
    ASSERT_EQ(info.parameters.size(), 1u);
    EXPECT_EQ(info.parameters[0].name, "k_h_per_percent");
    EXPECT_EQ(info.parameters[0].unit, "1/%");
    EXPECT_EQ(info.parameters[0].neutral, 0.0);
    EXPECT_EQ(parameterUnit("k_h_per_percent"), "1/%");
    EXPECT_EQ(info.user->data_variables, std::vector<std::string>{"humidity_percent"});
  }
  EXPECT_FALSE(parseTerm("humidity_abrasion", &t));  // the library is the built-in one again
  EXPECT_EQ(termLibrary().size(), static_cast<std::size_t>(Term::kFirstUser));
}

TEST(UserMechanisms, MalformedFilesNameTheLine) {
  ASSERT_EQ(compileError(document("output * exp(k * (humidity_percent - 50))", kParameter)), "");
  struct Case {
    std::string text;
    int line;
    std::string says;
  };
  const std::string ok = "output * exp(k * (humidity_percent - 50))";
  const std::vector<Case> cases = {
      {"mechanisms:\n  - name: [a\n", 3, "not a readable YAML document"},
      {"mechanism:\n  - name: x\n", 1, "unknown key 'mechanism'"},
      {document(ok, kParameter) + "    colour: red\n", 9, "unknown key 'colour'"},
      {document(ok, "{name: k, unit: 1/%, lower: -0.1, upper: 0.1, no_effect: 0, step: 1}"), 5, "unknown key 'step'"},
      {"mechanisms:\n  - name: x\n    statement: s\n", 2, "missing field 'parameters'"},
      {document(ok, "{name: k, unit: 1/%, lower: -0.1, upper: 0.1}"), 5, "missing field 'no_effect'"},
      {document(ok, "{name: k, unit: 1/%, lower: 0.1, upper: -0.1, no_effect: 0}"), 5, "must be < upper"},
      {document(ok, "{name: k, unit: 1/%, lower: 0.01, upper: 0.1, no_effect: 0}"), 5,
       "no_effect = 0 must be in [lower, upper]"},
      {document(ok, "{name: k, unit: 1/%, lower: -0.1, upper: 0.1, no_effect: 0, initial: 1}"), 5,
       "initial = 1 must be in [lower, upper]"},
      {document(ok, "{name: k, unit: 1/%, lower: -0.1, upper: nan, no_effect: 0}"), 5, "must be a finite number"},
      {document(ok, kParameter, "[wear, grip]"), 6, "unknown output 'grip'"},
      {document("output * (1 + k * (humidity_percent - 50)", kParameter), 8, "Missing parenthesis"},
      {document("output * exp(k * (humidity - 50))", kParameter), 8,
       "unknown variable humidity (valid: output, side_force_n, wear_kg_per_m, load_n"},
      {document(ok, kParameter, "[wear]", "sensor_gain"), 2, "the name is a built-in term"},
      {document(ok, "{name: q, unit: '-', lower: -0.1, upper: 0.1, no_effect: 0}"), 5, "parameter name 'q' is taken"},
      {document(ok, "{name: load_n, unit: '-', lower: -0.1, upper: 0.1, no_effect: 0}"), 5,
       "parameter name 'load_n' is taken"},
      {document(ok, kParameter) + document(ok, kParameter).substr(std::string("mechanisms:\n").size()), 9,
       "mechanism name 'my_term' is used twice"},
      {"mechanisms:\n  - name: x\n    statement: |\n      two\n      lines\n", 3, "must be one line"},
      {document(ok, kParameter) + "    test_magnitudes: [0.05, 0.2]\n", 9,
       "test_magnitudes entry 0.2 must be a value of k in [lower, upper]"},
      {document(ok, kParameter) + "    test_magnitudes: [0]\n", 9, "other than its no_effect"},
  };
  for (const Case& c : cases) {
    const std::string error = compileError(c.text);
    const std::string where = "m.yaml:" + std::to_string(c.line) + ": ";
    EXPECT_EQ(error.rfind(where, 0), 0u) << "want " << where << " in: " << error << "\n" << c.text;
    EXPECT_NE(error.find(c.says), std::string::npos) << "want '" << c.says << "' in: " << error;
  }
}

TEST(UserMechanisms, ExpressionsThatDoNotReduceToTheModelNameTheLine) {
  const TireParams base;
  const DiagnosisData data = buildDiagnosisData(concealEffect(base, spec("none", NAN, "small", 3)).table);
  Prediction model;
  ASSERT_TRUE(ExtendedModel(base, {}, {}, data).predict({1.0, 1.0}, &model));
  struct Case {
    std::string expression;
    std::string says;
  };
  for (const Case& c :
       std::vector<Case>{{"output * (1 + k) + 0.001 * output", "it must reduce to the model (`output`) there"},
                         {"output * (1 + k * (humidity_percent - 50)) / k", "it must be finite there"},
                         {"output + 1 / (humidity_percent - humidity_percent)", "it must be finite there"}}) {
    const TempFile file(document(c.expression, kParameter), ".yaml");
    const MechanismsInUse mechanisms(file.path());
    try {
      checkNoEffect(termLibrary().back(), data, model);
      ADD_FAILURE() << c.expression << ": no error";
    } catch (const DiagnosisError& e) {
      const std::string error = e.what();
      EXPECT_EQ(error.rfind(file.path() + ":8: mechanism 'my_term': at its no-effect values", 0), 0u) << error;
      EXPECT_NE(error.find(c.says), std::string::npos) << error;
    }
    // The diagnosis checks it before the selection.
    EXPECT_THROW(diagnose(base, data, quickOptions()), DiagnosisError) << c.expression;
  }
}

TEST(UserMechanisms, AtItsNoEffectValueTheMechanismIsTheModel) {
  const MechanismsInUse mechanisms(kExample);
  Term t;
  ASSERT_TRUE(parseTerm("humidity_abrasion", &t));
  const TireParams base;
  const ConcealCase c = concealEffect(base, spec("none", NAN, "small", 5));
  const DiagnosisData data = buildDiagnosisData(c.table);
  Prediction plain, neutral, effect;
  ASSERT_TRUE(ExtendedModel(base, {}, {}, data).predict({1.1, 0.95}, &plain));
  const ExtendedModel with(base, {}, {t}, data);
  ASSERT_TRUE(with.predict({1.1, 0.95, 0.0}, &neutral));
  ASSERT_TRUE(with.predict({1.1, 0.95, -0.02}, &effect));
  const std::vector<double>& humidity =
      data.covariates[std::find_if(data.covariates.begin(), data.covariates.end(),
                                   [](const Covariate& v) { return v.name == "humidity_percent"; }) -
                      data.covariates.begin()]
          .values;
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    EXPECT_EQ(neutral.side_force_n[i], plain.side_force_n[i]) << i;
    EXPECT_EQ(neutral.wear_kg_per_m[i], plain.wear_kg_per_m[i]) << i;
    EXPECT_EQ(effect.side_force_n[i], plain.side_force_n[i]) << i;  // wear only
    EXPECT_NEAR(effect.wear_kg_per_m[i] / plain.wear_kg_per_m[i], std::exp(-0.02 * (humidity[i] - 50.0)), 1e-12);
  }
}

// The tools end to end: tread_wear_conceal hides the example mechanism (k_h = -0.015 per %: +-15% wear over the
// generator's humidity spread of 10 %), tread_wear_diagnose with the same file selects it from the whole library.
TEST(UserMechanisms, ConcealedExampleMechanismIsSelectedThroughTheTools) {
  const std::string dir = testing::TempDir() + "tread_wear_user_mechanisms";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const CliResult conceal = runCli(
      [](int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
        return runConcealCli(argc, argv, {}, out, err);
      },
      {"--params", kParams, "--mechanisms", kExample, "--effect", "humidity_abrasion", "--magnitude", "-0.015",
       "--seed", "11", "--runs", dir + "/runs.csv", "--answer", dir + "/answer.json"});
  ASSERT_EQ(conceal.code, 0) << conceal.err;
  const CliResult r = diagnoseCli({"--params", kParams, "--runs", dir + "/runs.csv", "--mechanisms", kExample,
                                   "--report", dir + "/report", "--no-plots", "--detection-power", "0"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("explanation: humidity_abrasion\n"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir + "/report/diagnosis.json"));
  EXPECT_EQ(j["explanation"], "humidity_abrasion");
  EXPECT_EQ(j["explanation_terms"][0]["defined_in"], kExample + ":5");
  EXPECT_EQ(j["explanation_terms"][0]["parameters"][0]["unit"], "1/%");
  const double k = j["parameters"]["k_h_per_percent"]["value"];
  // Within 25% of the effect (the harness's criterion), and within 2 of its reported standard errors.
  EXPECT_NEAR(k, -0.015, 0.25 * 0.015);
  EXPECT_NEAR(k, -0.015, 2.0 * j["parameters"]["k_h_per_percent"]["std_error"].get<double>());
  EXPECT_EQ(j["parameters"]["k_h_per_percent"]["unit"], "1/%");
  EXPECT_LT(j["cv_rmser_after"]["wear"].get<double>(), 0.5 * j["cv_rmser_before"]["wear"].get<double>());
  // Without the file the name is unknown to the tools; a bad file is bad data (exit 1) naming its line.
  EXPECT_EQ(diagnoseCli({"--params", kParams, "--runs", dir + "/runs.csv", "--report", dir + "/r2", "--candidates",
                         "humidity_abrasion"})
                .code,
            2);
  const TempFile bad(document("output * exp(k * (humidity - 50))", kParameter), ".yaml");
  const CliResult b =
      diagnoseCli({"--params", kParams, "--runs", dir + "/runs.csv", "--mechanisms", bad.path(), "--report", dir});
  EXPECT_EQ(b.code, 1);
  EXPECT_NE(b.err.find(bad.path() + ":8: "), std::string::npos) << b.err;
  std::filesystem::remove_all(dir);
}

TEST(UserMechanisms, ControlsStayNoneWithTheMechanismsLoaded) {
  const MechanismsInUse mechanisms(kExample);
  const TireParams base = loadTireParams(kParams);
  for (std::uint64_t seed : {21, 22, 23}) {
    const DiagnosisData data = buildDiagnosisData(concealEffect(base, spec("none", NAN, "table2", seed)).table);
    const DiagnosisResult r = diagnose(base, data, quickOptions());
    EXPECT_EQ(r.explanation, "none") << "seed " << seed;
    EXPECT_TRUE(std::any_of(r.tried.begin(), r.tried.end(), [](const FittedModel& f) {
      return f.label == "humidity_abrasion";
    })) << "the user term was not tried";
  }
}

// An independent reference: a user mechanism restating sensor_gain (measured Fy = g Fy) must fit, cross-validate
// and bound like the built-in term.
TEST(UserMechanisms, RestatedBuiltInTermFitsAsTheBuiltIn) {
  const TempFile file(
      "mechanisms:\n  - name: gain_again\n    statement: the transducer reads g Fy\n    physical: false\n"
      "    parameters:\n      - {name: g, unit: '-', lower: 0.5, upper: 1.5, no_effect: 1}\n"
      "    affects: [side_force]\n    expression: g * output\n",
      ".yaml");
  const MechanismsInUse mechanisms(file.path());
  Term user;
  ASSERT_TRUE(parseTerm("gain_again", &user));
  const TireParams base = loadTireParams(kParams);
  const DiagnosisData data = buildDiagnosisData(concealEffect(base, spec("sensor_gain", 1.08, "small", 7)).table);
  DiagnosisOptions opt = quickOptions();
  opt.max_terms = 1;
  opt.detection_power = 0.8;
  opt.candidates = {Term::kSensorGain};
  const DiagnosisResult builtin = diagnose(base, data, opt);
  opt.candidates = {user};
  const DiagnosisResult restated = diagnose(base, data, opt);
  ASSERT_EQ(builtin.explanation, "sensor_gain");
  ASSERT_EQ(restated.explanation, "gain_again");
  double se_builtin, se_restated;
  const double g_builtin = fittedValue(builtin.final_model, "side_force_gain", &se_builtin);
  const double g_restated = fittedValue(restated.final_model, "g", &se_restated);
  EXPECT_NEAR(g_restated, g_builtin, 1e-6);
  EXPECT_NEAR(se_restated, se_builtin, 1e-6 * se_builtin);
  EXPECT_NEAR(restated.final_model.rss, builtin.final_model.rss, 1e-6 * builtin.final_model.rss);
  EXPECT_NEAR(restated.final_model.aicc, builtin.final_model.aicc, 1e-6);
  for (int o = 0; o < kNumOutputs; ++o)
    EXPECT_NEAR(restated.final_model.cv_rmser[o], builtin.final_model.cv_rmser[o], 1e-8) << o;
  ASSERT_EQ(builtin.detection_limits.size(), 1u);
  ASSERT_EQ(restated.detection_limits.size(), 1u);
  EXPECT_NEAR(restated.detection_limits[0].below, builtin.detection_limits[0].below, 1e-4);
  EXPECT_NEAR(restated.detection_limits[0].above, builtin.detection_limits[0].above, 1e-4);
}

// The harness takes a user mechanism's small and large magnitudes from its file (test_magnitudes).
TEST(UserMechanisms, HarnessScansTheFilesMagnitudes) {
  const MechanismsInUse mechanisms(kExample);
  HarnessOptions h;
  h.design = "small";
  h.repeats = 1;
  h.control_repeats = 1;
  h.wear_noise = {0.05};
  h.effects = {"humidity_abrasion"};
  h.diagnosis.permutations = 999;
  h.diagnosis.detection_power = 0.0;
  const std::vector<HarnessOutcome> outcomes = runHarness(loadTireParams(kParams), h);
  ASSERT_EQ(outcomes.size(), 3u);
  EXPECT_EQ(outcomes[0].c.magnitude_label, "small");
  EXPECT_EQ(outcomes[0].c.spec.magnitude, -0.005);
  EXPECT_EQ(outcomes[1].c.magnitude_label, "large");
  EXPECT_EQ(outcomes[1].c.spec.magnitude, -0.015);
  EXPECT_TRUE(outcomes[1].right) << outcomes[1].explanation;
  EXPECT_TRUE(outcomes[1].parameter_ok) << outcomes[1].estimate;
  EXPECT_TRUE(outcomes[1].improved);
  EXPECT_EQ(outcomes[2].explanation, "none");
  // A user term without test magnitudes cannot be scanned.
  const TempFile file(document("output * exp(k * (humidity_percent - 50))", kParameter), ".yaml");
  const MechanismsInUse other(file.path());
  h.effects = {"my_term"};
  EXPECT_THROW(harnessCases(h), std::invalid_argument);
}
