// Malformed inputs of the diagnosis tools get clear errors and the documented exit codes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/rig_run.h"
#include "common/temp_file.h"
#include "tread_wear/cli/diagnosis_cli.h"
#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/proving/harness.h"

using namespace tread_wear;
using namespace tread_wear::diagnosis;

namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
const std::string kParams = kSource + "/config/tires/grosch_wheel.yaml";

struct CliResult {
  int code;
  std::string out, err;
};

/// Runs one of the diagnosis command lines in-process with `program` as argv[0].
using CliFunction = std::function<int(int, const char* const[], std::ostream&, std::ostream&)>;
CliResult runCli(const std::string& program, const CliFunction& cli, std::vector<std::string> args) {
  args.insert(args.begin(), program);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  const int code = cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {code, out.str(), err.str()};
}

CliResult diagnoseCli(std::vector<std::string> args, const BagReader& reader = {}) {
  return runCli("tread_wear_diagnose",
                [&](int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
                  return runDiagnoseCli(argc, argv, reader, "", out, err);
                },
                std::move(args));
}

CliResult harnessCli(std::vector<std::string> args) {
  return runCli("tread_wear_diagnosis_harness", runHarnessCli, std::move(args));
}

CliResult concealCli(std::vector<std::string> args) {
  return runCli("tread_wear_conceal",
                [](int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
                  return runConcealCli(argc, argv, {}, out, err);
                },
                std::move(args));
}

}  // namespace

TEST(DiagnosisInputs, TooFewRuns) {
  RunTable t;
  for (int i = 0; i < 3; ++i) t.runs.push_back(rigRun(50.0));
  try {
    buildDiagnosisData(t);
    FAIL() << "expected DiagnosisError";
  } catch (const DiagnosisError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 4"), std::string::npos) << e.what();
  }
}

TEST(DiagnosisInputs, ZeroMeasurementNamesTheRun) {
  RunTable t;
  for (int i = 0; i < 5; ++i) t.runs.push_back(rigRun(50.0));
  t.runs[2].measured_side_force_n = 0.0;
  try {
    buildDiagnosisData(t);
    FAIL() << "expected DiagnosisError";
  } catch (const DiagnosisError& e) {
    EXPECT_NE(std::string(e.what()).find("run 3"), std::string::npos) << e.what();
  }
}

TEST(DiagnosisInputs, TermsNeedTheirCovariates) {
  RunTable t;
  for (int i = 0; i < 5; ++i) t.runs.push_back(rigRun(50.0 + i));
  const DiagnosisData d = buildDiagnosisData(t);
  std::string why;
  EXPECT_FALSE(termApplicable(Term::kThermalWear, d, &why));
  EXPECT_NE(why.find("temperature"), std::string::npos);
  EXPECT_FALSE(termApplicable(Term::kSurfacePolishing, d, &why));
  EXPECT_FALSE(termApplicable(Term::kLoadFluctuation, d, &why));
  EXPECT_TRUE(termApplicable(Term::kTurnSlipOrientation, d, &why));
  EXPECT_TRUE(termApplicable(Term::kLateralCompliance, d, &why));
}

TEST(DiagnosisInputs, CliUsageErrors) {
  EXPECT_EQ(diagnoseCli({"--runs", "x.csv", "--report", "r"}).code, 2);  // no --params
  EXPECT_EQ(diagnoseCli({"--params", kParams, "--runs", "a.csv", "--bag", "b.bag", "--report", "r"}).code, 2);
  const CliResult bag = diagnoseCli({"--params", kParams, "--bag", "b.bag", "--report", "r"});
  EXPECT_EQ(bag.code, 2);
  EXPECT_NE(bag.err.find("rosbag"), std::string::npos) << bag.err;
  const CliResult cand =
      diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--candidates", "magic"});
  EXPECT_EQ(cand.code, 2);
  EXPECT_NE(cand.err.find("'magic'"), std::string::npos) << cand.err;
  EXPECT_EQ(diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--max-terms", "x"}).code, 2);
  EXPECT_EQ(diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--alpha-select", "2"}).code, 2);
  const CliResult power =
      diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--detection-power", "1"});
  EXPECT_EQ(power.code, 2);
  EXPECT_NE(power.err.find("detection_power = 1"), std::string::npos) << power.err;
  EXPECT_EQ(diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "stray"}).code, 2);
  // Issue 26's options: a preset and a noise model that do not exist.
  const CliResult preset = diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--preset", "ultra"});
  EXPECT_EQ(preset.code, 2);
  EXPECT_NE(preset.err.find("--preset must be auto, fast"), std::string::npos) << preset.err;
  EXPECT_NE(preset.err.find("'ultra'"), std::string::npos) << preset.err;
  const CliResult noise =
      diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--force-noise-model", "poisson"});
  EXPECT_EQ(noise.code, 2);
  EXPECT_NE(noise.err.find("--force-noise-model must be auto, additive, relative or combined, got 'poisson'"),
            std::string::npos)
      << noise.err;
  EXPECT_EQ(diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--wear-noise-model", "gauss"}).code,
            2);
  // A calibration of held-out groups without its level (refused before any recording is read: a.csv does not exist)
  for (const char* spec : {"test", "=Run-in", "test=", ""}) {
    const CliResult calibrate =
        diagnoseCli({"--params", kParams, "--runs", "a.csv", "--report", "r", "--cv-calibrate", spec});
    EXPECT_EQ(calibrate.code, 2) << spec;
    EXPECT_NE(calibrate.err.find("expected COVARIATE=LEVEL"), std::string::npos) << calibrate.err;
  }
}

TEST(DiagnosisInputs, CliDataErrors) {
  const CliResult missing = diagnoseCli({"--params", kParams, "--runs", "/nonexistent/runs.csv", "--report", "r"});
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("/nonexistent/runs.csv"), std::string::npos) << missing.err;
  // A run table that reaches the diagnosis and is refused there: exit 1, the message names the problem.
  auto expectDataError = [](const std::string& table, const std::string& expected) {
    const TempFile runs("# tread_wear run table v1\n" + table, ".csv");
    const CliResult r = diagnoseCli({"--params", kParams, "--runs", runs.path(), "--report", "r"});
    EXPECT_EQ(r.code, 1) << table;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  };
  expectDataError("speed_mps,slip_angle_rad,load_n\n2,abc,75\n", "slip_angle_rad");
  expectDataError("speed_mps,slip_angle_rad,load_n,side_force_n\n2,-0.17,75,50\n2,-0.17,75,51\n", "at least 4");
  expectDataError("speed_mps,slip_angle_rad,load_n,side_force_n\n"
                  "2,-0.17,75,-50\n2,-0.17,75,-51\n2,-0.17,75,-49\n2,-0.17,75,-52\n",
                  "axis convention");
  const CliResult bad_bag =
      diagnoseCli({"--params", kParams, "--bag", "x.bag", "--report", "r"},
                  [](const std::string& p, const TireParams&, const ReplaySettings&) -> RunTable { throw std::runtime_error(p + ": not a bag"); });
  EXPECT_EQ(bad_bag.code, 1);
  EXPECT_NE(bad_bag.err.find("x.bag: not a bag"), std::string::npos) << bad_bag.err;
}

TEST(DiagnosisInputs, ConcealErrors) {
  EXPECT_EQ(concealCli({"--params", kParams, "--effect", "magic", "--runs", "a.csv", "--answer", "a.json"}).code, 2);
  EXPECT_EQ(concealCli({"--params", kParams, "--effect", "none", "--runs", "a.csv"}).code, 2);
  EXPECT_EQ(concealCli({"--params", kParams, "--effect", "none", "--runs", "a.csv", "--answer", "a.json",
                        "--design", "huge"}).code, 2);
  const CliResult drives = concealCli(
      {"--params", kParams, "--effect", "none", "--runs", "a.csv", "--answer", "a.json", "--design", "drives"});
  EXPECT_EQ(drives.code, 2);
  EXPECT_NE(drives.err.find("tread_wear_diagnosis_harness --design drives"), std::string::npos) << drives.err;
  EXPECT_EQ(
      concealCli({"--params", "/nonexistent.yaml", "--effect", "none", "--runs", "a.csv", "--answer", "a.json"}).code,
      1);
  const CliResult list = concealCli({"--list"});
  EXPECT_EQ(list.code, 0);
  for (const TermInfo& t : termLibrary()) EXPECT_NE(list.out.find(t.name), std::string::npos) << t.name;
}

// tread_wear_conceal --information writes the case's detectability reference into the answer file: the oracle's
// verdict shares (a distribution over the draws) with expected_right the hidden term's share, the F-test power,
// and the reference standard errors; it needs noise to measure against.
TEST(DiagnosisInputs, ConcealWritesTheDetectabilityReference) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "tread_wear_conceal_information";
  fs::create_directories(dir);
  const std::string runs = (dir / "runs.csv").string(), answer_path = (dir / "answer.json").string();
  const CliResult r = concealCli({"--params", kParams, "--effect", "sensor_offset", "--magnitude", "2", "--design",
                                  "small", "--seed", "3", "--runs", runs, "--answer", answer_path, "--information",
                                  "--generator-preset", "fast"});  // the reference's model: the value exactly
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("detectability reference: lambda "), std::string::npos) << r.out;
  std::ifstream f(answer_path);
  const nlohmann::json answer = nlohmann::json::parse(f);
  const nlohmann::json& d = answer.at("detectability");
  double total = 0.0;
  for (const auto& [verdict, share] : d.at("verdicts").items()) total += share.get<double>();
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(d.at("expected_right").get<double>(), d.at("verdicts").at("sensor_offset").get<double>());
  EXPECT_GT(d.at("power").get<double>(), 0.0);
  EXPECT_LE(d.at("power").get<double>(), 1.0);
  EXPECT_GT(d.at("parameters").at("side_force_offset_n").at("std_error").get<double>(), 0.0);
  EXPECT_NEAR(d.at("parameters").at("side_force_offset_n").at("value").get<double>(), 2.0, 1e-6);
  const CliResult no_noise = concealCli({"--params", kParams, "--effect", "sensor_offset", "--runs", runs, "--answer",
                                         answer_path, "--force-noise", "0", "--information"});
  EXPECT_EQ(no_noise.code, 2);
  EXPECT_NE(no_noise.err.find("--information needs"), std::string::npos) << no_noise.err;
}

// The success-rate table counts each wear-noise level on its own: totals per level, controls apart.
// The two readings of "parameter within 25%": of the effect (gain 1.05 -> 1.07 is 40% of the 0.05 effect off) and
// of the value (2% of 1.05); a wrong explanation meets neither, and improved is needed for "all three".
TEST(DiagnosisHarness, ParameterReadings) {
  ConcealAnswer answer;
  answer.effect = "sensor_gain";
  answer.primary = "side_force_gain";
  answer.primary_value = 1.05;
  answer.primary_neutral = 1.0;
  DiagnosisResult result;
  result.explanation = "sensor_gain";
  result.final_model.terms = {Term::kSensorGain};
  ParameterEstimate gain;
  gain.name = "side_force_gain";
  gain.value = 1.07;
  result.final_model.summary.parameters = {gain};
  result.base.cv_rmser[0] = 0.03;
  result.final_model.cv_rmser[0] = 0.02;
  HarnessOutcome o = scoreCase(HarnessCase{}, answer, result);
  EXPECT_TRUE(o.right);
  EXPECT_FALSE(o.parameter_ok);
  EXPECT_TRUE(o.parameter_ok_relative);
  EXPECT_TRUE(o.improved);
  EXPECT_FALSE(o.all_met);
  result.final_model.summary.parameters[0].value = 1.06;  // 20% of the effect off
  o = scoreCase(HarnessCase{}, answer, result);
  EXPECT_TRUE(o.parameter_ok && o.all_met);
  result.final_model.cv_rmser[0] = 0.04;  // worse out of sample
  EXPECT_FALSE(scoreCase(HarnessCase{}, answer, result).all_met);
  result.explanation = "sensor_offset";
  result.final_model.terms = {Term::kSensorOffset};
  o = scoreCase(HarnessCase{}, answer, result);
  EXPECT_FALSE(o.right || o.parameter_ok || o.parameter_ok_relative || o.all_met);
}

TEST(DiagnosisHarness, TableTotalsPerNoiseLevel) {
  auto outcome = [](const std::string& effect, double noise, bool right) {
    HarnessOutcome o;
    o.c.spec.effect = effect;
    o.c.spec.wear_noise_rsd = noise;
    o.c.magnitude_label = effect == "none" ? "-" : "small";
    o.right = right;
    return o;
  };
  std::vector<HarnessOutcome> outcomes = {
      outcome("sensor_gain", 0.05, true), outcome("sensor_gain", 0.05, false), outcome("none", 0.05, true),
      outcome("sensor_gain", 0.10, true), outcome("none", 0.10, false), outcome("none", 0.10, true)};
  // Parameters: scored for the two 5% gain cases, the term selected (estimated) in the first only, where the
  // estimate is within 25% and the truth inside 2 standard errors.
  for (int k : {0, 1}) outcomes[k].parameter_scored = true;
  outcomes[0].parameter_estimated = outcomes[0].parameter_covered = outcomes[0].parameter_ok = true;
  outcomes[0].parameter_ok_relative = outcomes[0].all_met = true;
  // Named: the right case, and the wrong 5% case whose hidden term was reported as a close alternative.
  for (int k : {0, 1, 3}) outcomes[k].named = true;
  const std::string table = harnessTable(outcomes);
  // Summary rates carry 95% Wilson intervals (1/2: 9.5-90.5%, 1/1: 20.7-100%, by hand from Newcombe's formula).
  EXPECT_NE(table.find("At wear RSD 5%: right explanation 50.0% (1/2) [95% CI 9.5-90.5%], parameter within 25% "
                       "50.0% (1/2) [95% CI 9.5-90.5%] (when selected, truth within 2 standard errors 100% (1/1) "
                       "[95% CI 20.7-100.0%])"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("controls `none` 100% (1/1) [95% CI 20.7-100.0%]. Parameter within 25% of its own value "
                       "(|estimate - truth| <= 0.25 |truth|) 50.0% (1/2) [95% CI 9.5-90.5%]; right, parameter and "
                       "improved in the same case 50.0% (1/2) [95% CI 9.5-90.5%]. The hidden term named as the "
                       "explanation or as a close alternative 100% (2/2) [95% CI 34.2-100.0%]."),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("At wear RSD 10%: right explanation 100% (1/1)"), std::string::npos) << table;
  EXPECT_NE(table.find("controls `none` 50.0% (1/2) [95% CI 9.5-90.5%]."), std::string::npos) << table;
}

TEST(DiagnosisHarness, TableShowsTheDetectabilityReference) {
  // Two gain cases whose references are 0.9 and 0.6 (parameter 0.8 and 0.4) and a control with 0.99: the columns
  // hold their means.
  auto outcome = [](const std::string& effect, bool right, double reference, double parameter) {
    HarnessOutcome o;
    o.c.spec.effect = effect;
    o.c.spec.wear_noise_rsd = 0.05;
    o.c.magnitude_label = effect == "none" ? "-" : "small";
    o.right = right;
    o.information = true;
    o.reference.hidden = effect;
    o.reference.expected_right = reference;
    o.reference_parameter_ok = parameter;
    return o;
  };
  const std::string table = harnessTable({outcome("sensor_gain", true, 0.9, 0.8),
                                          outcome("sensor_gain", false, 0.6, 0.4),
                                          outcome("none", true, 0.99, std::nan(""))});
  EXPECT_NE(table.find("| right explanation | expected right (detectability reference) | parameter within 25% | "
                       "expected parameter within 25% (reference) | held-out RMSER improved |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| sensor_gain | small | 5% | 2 | 50.0% (1/2) | 75.0% | - | 60.0% | - |"), std::string::npos)
      << table;
  EXPECT_NE(table.find("| none | 5% | 1 | 100% (1/1) | 99.0% | - | - | - | - |"), std::string::npos) << table;
  EXPECT_NE(table.find("expected right explanation 75.0% of the hidden effects, parameter within 25% 60.0%, `none` "
                       "99.0% of the controls."),
            std::string::npos)
      << table;
  // The CSV carries the reference beside the outcome: lambda, power, expected right, parameter, and the oracle's
  // most likely wrong verdict with its share.
  HarnessOutcome with_verdicts = outcome("sensor_gain", true, 0.9, 0.8);
  with_verdicts.reference.lambda = 15.0;
  with_verdicts.reference.power = 0.7;
  with_verdicts.reference.verdicts = {{"sensor_gain", 0.9}, {"sensor_offset", 0.07}, {"none", 0.03}};
  const std::string csv_text = harnessCsv({with_verdicts});
  const std::string header = csv_text.substr(0, csv_text.find('\n'));
  const std::string line = csv_text.substr(header.size() + 1);
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), std::count(line.begin(), line.end(), ',')) << csv_text;
  EXPECT_NE(header.find(",reference_lambda,reference_power,reference_expected_right,reference_parameter_ok,"
                        "reference_top_wrong,reference_top_wrong_share,"),
            std::string::npos);
  EXPECT_NE(line.find(",15,0.7,0.9,0.8,sensor_offset,0.07,"), std::string::npos) << line;
  // A case whose reference failed still counts for the measured rates and is named in the summary.
  HarnessOutcome failed = outcome("sensor_gain", true, 0.0, std::nan(""));
  failed.information = false;
  failed.reference_error = "the base model cannot be fitted to the truth";
  const std::string with_failure = harnessTable({outcome("sensor_gain", true, 0.9, 0.8), failed});
  EXPECT_NE(with_failure.find("| sensor_gain | small | 5% | 2 | 100% (2/2) | 90.0% |"), std::string::npos)
      << with_failure;
  EXPECT_NE(with_failure.find("; 1 case(s) without a reference, see the progress log."), std::string::npos)
      << with_failure;
  // Without references the table has no such column.
  HarnessOutcome plain = outcome("sensor_gain", true, 0.9, 0.8);
  plain.information = false;
  plain.reference_parameter_ok = std::nan("");
  EXPECT_EQ(harnessTable({plain}).find("reference"), std::string::npos);
}

// The harness from the command line: a two-case run with the detectability reference, and the usage errors.
TEST(DiagnosisHarnessCli, RunsWithTheReferenceAndRejectsBadUsage) {
  const CliResult r = harnessCli({"--params", kParams, "--quick", "--effects", "sensor_offset", "--repeats", "1",
                                  "--controls", "1", "--information"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| sensor_offset | default | 5% | 1 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Detectability reference"), std::string::npos) << r.out;
  const CliResult zero_noise = harnessCli({"--params", kParams, "--quick", "--noise", "0", "--information"});
  EXPECT_EQ(zero_noise.code, 2);
  EXPECT_NE(zero_noise.err.find("--information needs every --noise level > 0"), std::string::npos) << zero_noise.err;
  EXPECT_EQ(harnessCli({"--quick"}).code, 2);  // no --params
  EXPECT_EQ(harnessCli({"--params", kParams, "--repeats", "0"}).code, 2);
  EXPECT_EQ(harnessCli({"--params", kParams, "--effects", "magic"}).code, 2);
  EXPECT_EQ(harnessCli({"--params", kParams, "--noise", "0.9"}).code, 2);
  const CliResult generator = harnessCli({"--params", kParams, "--generator-preset", "auto"});
  EXPECT_EQ(generator.code, 2);
  EXPECT_NE(generator.err.find("--generator-preset must be fast, standard, fine or reference, got 'auto'"),
            std::string::npos)
      << generator.err;
  EXPECT_EQ(harnessCli({"--params", kParams, "--wear-noise-model", "additiv"}).code, 2);
  const CliResult alpha = harnessCli({"--params", kParams, "--alpha-select", "1.5"});
  EXPECT_EQ(alpha.code, 2);
  EXPECT_NE(alpha.err.find("alpha_select"), std::string::npos) << alpha.err;
  EXPECT_EQ(harnessCli({"--params", kSource + "/no/such/file.yaml", "--quick", "--effects", "sensor_offset"}).code, 1);
  // Design drives: its fleet options are required with it and refused without it; rough_road is its effect only.
  const CliResult no_fleet = harnessCli({"--params", kParams, "--design", "drives"});
  EXPECT_EQ(no_fleet.code, 2);
  EXPECT_NE(no_fleet.err.find("--design drives needs --vehicles and --profile"), std::string::npos) << no_fleet.err;
  const CliResult stray = harnessCli({"--params", kParams, "--quick", "--checkpoints", "5"});
  EXPECT_EQ(stray.code, 2);
  EXPECT_NE(stray.err.find("--checkpoints is an option of --design drives only"), std::string::npos) << stray.err;
  EXPECT_EQ(harnessCli({"--params", kParams, "--quick", "--effects", "rough_road"}).code, 2);
  const CliResult few = harnessCli({"--params", kParams, "--design", "drives", "--vehicles",
                                    kSource + "/config/vehicle_passenger_car.yaml", "--profile",
                                    kSource + "/data/wltc_class3b.csv", "--checkpoints", "1"});
  EXPECT_EQ(few.code, 2);
  EXPECT_NE(few.err.find("checkpoints = 1 must be >= 2"), std::string::npos) << few.err;
}

// The documented example (examples/diagnosis/README.md) end to end through the command line: exit 0, the verdict
// on stdout, and in the report directory report.md, the PNG plots and diagnosis.json with the fields the issue
// names. The truth is the generator's answer file, which the diagnosis never reads.
TEST(DiagnosisCli, DocumentedExampleWritesTheReport) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "tread_wear_diagnosis_example";
  fs::remove_all(dir);
  const CliResult r = diagnoseCli({"--params", kParams, "--runs", kSource + "/examples/diagnosis/polishing_runs.csv",
                                   "--report", dir.string(), "--plot-script", kSource + "/scripts/plot_diagnosis.py"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("mismatch_found: true\nexplanation: surface_polishing\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("held-out RMSER: side force "), std::string::npos) << r.out;

  std::ifstream report_file(dir / "report.md");
  const std::string report((std::istreambuf_iterator<char>(report_file)), {});
  EXPECT_NE(report.find("- explanation: **surface_polishing**"), std::string::npos) << report;
  for (const char* png : {"residuals_side_force.png", "residuals_wear.png", "measured_vs_predicted.png"}) {
    EXPECT_GT(fs::exists(dir / png) ? fs::file_size(dir / png) : 0, 1000u) << png;
    EXPECT_NE(report.find(std::string("](") + png + ")"), std::string::npos) << png;
  }

  nlohmann::json j, answer;
  std::ifstream(dir / "diagnosis.json") >> j;
  std::ifstream(kSource + "/examples/diagnosis/polishing_answer.json") >> answer;
  EXPECT_EQ(j["mismatch_found"], true);
  EXPECT_EQ(j["explanation"], "surface_polishing");
  EXPECT_TRUE(j["close_alternatives"].empty()) << "no other term fits about as well";
  // Located: the wear residual follows the sliding distance on the current surface, significantly.
  ASSERT_FALSE(j["located"].empty());
  EXPECT_EQ(j["located"][0]["output"], "wear");
  EXPECT_EQ(j["located"][0]["covariate"], "cumulative_sliding_m");
  EXPECT_LT(j["located"][0]["p_adjusted"].get<double>(), 0.01);
  const nlohmann::json& rate = j["parameters"][answer["primary"].get<std::string>()];
  const double truth = answer["primary_value"];
  EXPECT_NEAR(rate["value"].get<double>(), truth, 0.25 * truth);
  EXPECT_GT(rate["std_error"].get<double>(), 0.0);
  EXPECT_LT(j["cv_rmser_after"]["wear"].get<double>(), j["cv_rmser_before"]["wear"].get<double>());
  // What the recordings could show: the polishing that was found lies beyond its detection limit.
  EXPECT_NE(report.find("## What these recordings could have shown"), std::string::npos);
  EXPECT_EQ(j["detection_limits"]["power"], 0.8);
  const nlohmann::json& limit = j["detection_limits"]["terms"]["surface_polishing"];
  EXPECT_EQ(limit["parameter"], answer["primary"]);
  EXPECT_TRUE(limit["below"].is_null()) << "a polishing rate cannot be negative";
  EXPECT_GT(rate["value"].get<double>(), limit["above"].get<double>());
  EXPECT_NEAR(j["noise_left"]["wear_rsd"].get<double>(), answer["wear_noise_rsd"].get<double>(), 0.02);
  EXPECT_NEAR(j["noise_left"]["side_force_n"].get<double>(), answer["side_force_noise_n"].get<double>(), 0.4);
  for (const char* name : {"w3_scale", "mu_scale"}) {
    const nlohmann::json& shift = j["base_parameter_shift"][name];
    EXPECT_NEAR(shift["relative"].get<double>(),
                shift["after"].get<double>() / shift["before"].get<double>() - 1.0, 1e-12) << name;
  }
  // Issue 26: the preset decision and every check behind it, on stderr, in report.md and in diagnosis.json; the last
  // check is at the explanation and passed (auto escalates until it does).
  const nlohmann::json& numerics = j["numerics"];
  EXPECT_NE(r.err.find(numerics["decision"].get<std::string>()), std::string::npos) << r.err;
  EXPECT_NE(report.find("## Numerics and noise model"), std::string::npos);
  ASSERT_FALSE(numerics["checks"].empty());
  const nlohmann::json& last = numerics["checks"].back();
  EXPECT_EQ(last["preset"], numerics["preset"]);
  EXPECT_EQ(last["at_model"], "surface_polishing");
  EXPECT_EQ(last["passed"], true);
  EXPECT_LE(last["noncentrality"].get<double>(), last["limit"].get<double>());
  for (const char* output : {"side_force", "wear"}) {
    const nlohmann::json& noise = j["noise_models"][output];
    EXPECT_TRUE(noise["kind"] == "additive" || noise["kind"] == "relative" || noise["kind"] == "combined") << output;
    EXPECT_EQ(last["outputs"][output]["values"], 36) << output;
  }
}

// A `none` prints what it rules out: each term's detection limits, as in diagnosis.json.
TEST(DiagnosisCli, NoneSaysWhatItRulesOut) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "tread_wear_diagnosis_none";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string runs = (dir / "runs.csv").string();
  ASSERT_EQ(concealCli({"--params", kParams, "--effect", "none", "--design", "small", "--seed", "21", "--runs", runs,
                        "--answer", (dir / "answer.json").string()})
                .code,
            0);
  const CliResult r = diagnoseCli({"--params", kParams, "--runs", runs, "--report", (dir / "report").string(),
                                   "--no-plots"});
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_NE(r.out.find("explanation: none\n"), std::string::npos) << r.out;
  nlohmann::json j;
  std::ifstream(dir / "report" / "diagnosis.json") >> j;
  const nlohmann::json& offset = j["detection_limits"]["terms"]["sensor_offset"];
  char expected[160];
  std::snprintf(expected, sizeof(expected),
                "would have found (power 0.8): sensor_offset side_force_offset_n <= %.3g or >= %.3g\n",
                offset["below"].get<double>(), offset["above"].get<double>());
  EXPECT_NE(r.out.find(expected), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(": load_fluctuation"), std::string::npos) << "no limit, so no line: " << r.out;
}
