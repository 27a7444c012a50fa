// scripts/leon_t_diagnosis_input.py (the LEON-T measured tests as diagnosis input, docs/leon_t_diagnosis.md) on
// bad measurements: wrong columns, a NaN, a set without a test's runs, a negative value, an unknown --sets entry;
// each exits 1 naming the file, the line or the missing runs, before any drive is generated (--check-only). And the
// package's data pass, with the section plan the docs state.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>

#include "../common/temp_file.h"

namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;

struct Outcome {
  int exit_code;
  std::string output;  ///< stdout and stderr
};

Outcome runScript(const std::string& measurements, const std::string& extra = "") {
  const std::string cmd = "/usr/bin/python3 " + kSource + "/scripts/leon_t_diagnosis_input.py --out " +
                          testing::TempDir() + "leon_t_input_unused --check-only" +
                          (measurements.empty() ? "" : " --measurements " + measurements) + " " + extra + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  Outcome o{-1, ""};
  if (!pipe) return o;
  std::array<char, 256> buf;
  while (fgets(buf.data(), buf.size(), pipe.get())) o.output += buf.data();
  const int status = pclose(pipe.release());
  o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

/// One set (brand A, Standard), complete: four tests on four wheels, one repeat each, except what `skip` names.
std::string oneSet(const std::string& skip = "", const std::string& value = "50.0") {
  std::string csv = "tyre_brand,scenario,wheel,test,repeat,abrasion_mg_per_km\n";
  for (const char* test : {"Run-in", "Rural", "Motorway", "Urban"})
    for (const char* wheel : {"FL", "FR", "RL", "RR"}) {
      if (skip == std::string(wheel) + " " + test) continue;
      csv += std::string("A,Standard,") + wheel + "," + test + ",R1," +
             (std::string(wheel) == "FL" && std::string(test) == "Rural" ? value : "50.0") + "\n";
    }
  return csv;
}

}  // namespace

TEST(LeonTDiagnosisInput, PackageDataPassWithTheDocumentedPlan) {
  const Outcome o = runScript("");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NE(o.output.find("Rural    Rural_60_kph x1, Rural_70_kph x2, Rural_80_kph x2"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("Urban_cs_20kph x3, Urban_br_20kph x1, Urban_pa_30kph x5, Urban_pa_40kph x6"),
            std::string::npos);
  EXPECT_NE(o.output.find("sets: Goodyear/Standard, LingLong/High load, LingLong/High temperature, "
                          "LingLong/Standard, Michelin/Standard"),
            std::string::npos);
}

TEST(LeonTDiagnosisInput, CompleteSetPasses) {
  const TempFile f(oneSet(), ".csv");
  const Outcome o = runScript(f.path());
  EXPECT_EQ(o.exit_code, 0) << o.output;
}

TEST(LeonTDiagnosisInput, WrongColumnsAreRefused) {
  std::string csv = oneSet();
  csv.replace(0, csv.find('\n'), "brand,scenario,wheel,test,repeat,abrasion_mg_per_km");
  const TempFile f(csv, ".csv");
  const Outcome o = runScript(f.path());
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_NE(o.output.find("line 1: columns brand,scenario"), std::string::npos) << o.output;
}

TEST(LeonTDiagnosisInput, NanAndNonPositiveValuesAreRefusedWithTheirLine) {
  for (const char* bad : {"nan", "-3.0", "0", "abc", "inf"}) {
    const TempFile f(oneSet("", bad), ".csv");
    const Outcome o = runScript(f.path());
    EXPECT_EQ(o.exit_code, 1) << bad;
    // FL Rural is the fifth data row: line 6
    EXPECT_NE(o.output.find("line 6: column abrasion_mg_per_km: '" + std::string(bad) + "'"), std::string::npos)
        << o.output;
  }
}

TEST(LeonTDiagnosisInput, MissingRunsOfASetAreRefused) {
  const TempFile f(oneSet("RL Urban"), ".csv");
  const Outcome o = runScript(f.path());
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_NE(o.output.find("A/Standard has no runs for RL Urban"), std::string::npos) << o.output;
}

TEST(LeonTDiagnosisInput, UnknownSetIsRefused) {
  const TempFile f(oneSet(), ".csv");
  const Outcome o = runScript(f.path(), "--sets B/Standard");
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_NE(o.output.find("'B/Standard' has no measurements"), std::string::npos) << o.output;
}

TEST(LeonTDiagnosisInput, ShortRowIsRefused) {
  const TempFile f(oneSet() + "A,Standard,FL\n", ".csv");
  const Outcome o = runScript(f.path());
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_NE(o.output.find("line 18: 3 fields, expected 6"), std::string::npos) << o.output;
}
