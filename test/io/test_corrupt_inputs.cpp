// Corrupt files (run tables, tire and vehicle parameter files, condition tables, speed profiles, node state
// files): seeded random mutations of valid inputs (bytes flipped, spans deleted or repeated, tokens such
// as "nan", "," or "{" inserted, the file cut short) are either read as valid data or rejected with a
// std::exception that names the file; never a crash, another exception type or invalid data let through. Under
// scripts/run_sanitizers.sh this also checks every parser for memory errors on such input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "common/temp_file.h"
#include "tread_wear/diagnosis/data.h"
#include "tread_wear/io/conditions_csv.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/io/speed_profile_csv.h"
#include "tread_wear/io/state_store.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/vehicle/speed_profile.h"
#include "tread_wear/vehicle/vehicle_model.h"

namespace tread_wear {
namespace {

constexpr int kMutants = 2000;

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// 1-4 random edits of `text`.
std::string mutate(std::string text, std::mt19937* rng) {
  static const char* const kTokens[] = {",", "\n", "nan", "inf", "-1", "1e308", "#", "\"", ":", "- ",
                                        "{",  "}",  "[",   "]",   "0",  " ",     "\t", "\r\n", "1e-320", "-0"};
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>((*rng)() % n); };
  const int edits = 1 + static_cast<int>(pick(4));
  for (int i = 0; i < edits && !text.empty(); ++i) {
    const std::size_t at = pick(text.size());
    switch (pick(5)) {
      case 0: text[at] = static_cast<char>(pick(256)); break;
      case 1: text.erase(at, 1 + pick(20)); break;
      case 2: text.insert(at, kTokens[pick(sizeof(kTokens) / sizeof(kTokens[0]))]); break;
      case 3: text.insert(at, text.substr(pick(text.size()), 1 + pick(40))); break;
      default: text.resize(at); break;
    }
  }
  return text;
}

struct Outcome {
  int accepted = 0;
  int rejected = 0;
};

/// Feeds kMutants mutants of `valid` to `read`, which returns normally for data it accepts (and checks them) or
/// throws; a rejection must be a std::exception whose message contains `name_in_message`.
Outcome mutants(const std::string& valid, unsigned seed, const std::string& name_in_message,
                const std::function<void(const std::string&)>& read) {
  std::mt19937 rng(seed);
  Outcome o;
  for (int i = 0; i < kMutants; ++i) {
    const std::string text = mutate(valid, &rng);
    try {
      read(text);
      ++o.accepted;
    } catch (const std::exception& e) {
      ++o.rejected;
      EXPECT_NE(std::string(e.what()).find(name_in_message), std::string::npos)
          << "mutant " << i << ": '" << e.what() << "' does not name " << name_in_message;
    } catch (...) {
      ADD_FAILURE() << "mutant " << i << ": an exception that is not a std::exception";
    }
  }
  return o;
}

TEST(CorruptInputs, RunTables) {
  const std::string valid = readFile("examples/diagnosis/polishing_runs.csv");
  ASSERT_FALSE(valid.empty());
  int diagnosable = 0;
  const Outcome o = mutants(valid, 1, ".csv", [&](const std::string& text) {
    const TempFile file(text, ".csv");
    const RunTable table = readRunTable(file.path());
    std::string error;
    for (const RunRecord& r : table.runs) EXPECT_TRUE(r.op.validate(&error)) << error;
    try {  // a table the reader accepts may still lack what a diagnosis needs; that is a named error too
      diagnosis::buildDiagnosisData(table);
      ++diagnosable;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()), "");
    }
  });
  EXPECT_GT(o.accepted, 0);
  EXPECT_GT(o.rejected, 0);
  EXPECT_GT(diagnosable, 0);
}

/// Mutants of the parameter file at `path` (repo-relative): an accepted one must pass the params' validate().
template <typename Load>
void parameterFileMutants(const std::string& path, unsigned seed, Load load) {
  const std::string valid = readFile(path);
  ASSERT_FALSE(valid.empty());
  const Outcome o = mutants(valid, seed, ".yaml", [&](const std::string& text) {
    const TempFile file(text, ".yaml");
    std::string error;
    EXPECT_TRUE(load(file.path()).validate(&error)) << error;
  });
  EXPECT_GT(o.accepted, 0);
  EXPECT_GT(o.rejected, 0);
}

TEST(CorruptInputs, TireParameterFiles) { parameterFileMutants("config/tires/grosch_wheel.yaml", 2, loadTireParams); }

TEST(CorruptInputs, ConditionTables) {
  const std::string valid =
      "speed_mps,slip_angle_rad,slip_ratio,path_radius_m,load_n\n2,0.1,0,0,75\n20,0.05,-0.1,50,4000\n"
      "0.5,0,0.2,,100\n\"3\",0.2,0.01,-20,60\n";
  const Outcome o = mutants(valid, 3, "mutant.csv", [](const std::string& text) {
    std::istringstream in(text);
    const ConditionsTable t = readConditions(in, "mutant.csv");
    std::string error;
    for (const OperatingPoint& p : t.points) EXPECT_TRUE(p.validate(&error)) << error;
  });
  EXPECT_GT(o.accepted, 0);
  EXPECT_GT(o.rejected, 0);
}

// A driving cycle (the first two minutes of WLTC class 3b, with its phase line): an accepted profile is one the
// drive generator can use, finite and non-negative speed and distance over its whole span.
TEST(CorruptInputs, SpeedProfiles) {
  std::istringstream wltc(readFile("data/wltc_class3b.csv"));
  std::string valid, line;
  for (int n = 0; n < 123 && std::getline(wltc, line); ++n) valid += line + "\n";
  ASSERT_NE(valid.find("# Phases:"), std::string::npos);
  const Outcome o = mutants(valid, 5, ".csv", [](const std::string& text) {
    const TempFile file(text, ".csv");
    const SpeedProfile profile = loadSpeedProfile(file.path());
    EXPECT_GT(profile.duration_s(), 0.0);
    for (double t = profile.startTime_s(); t <= profile.endTime_s(); t += 0.5) {
      EXPECT_TRUE(std::isfinite(profile.speed(t)) && profile.speed(t) >= 0.0) << t;
      EXPECT_TRUE(std::isfinite(profile.distance(t)) && profile.distance(t) >= 0.0) << t;
    }
  });
  EXPECT_GT(o.accepted, 0);
  EXPECT_GT(o.rejected, 0);
}

TEST(CorruptInputs, VehicleParameterFiles) {
  parameterFileMutants("config/vehicle_passenger_car.yaml", 6, loadVehicleParams);
}

// The node's state file: what it cannot use is reported (fromJson false with a reason), never loaded as
// non-finite or negative accumulated values.
TEST(CorruptInputs, StateFiles) {
  StateFile state;
  state.saved_unix_s = 1.79e9;
  state.wheels = {{"front_left", "tire-a", 1.5e-4, 12345.6, 1.7e9}, {"rear_left", "", 0.0, 0.0, 0.0}};
  const Outcome o = mutants(StateStore::toJson(state), 4, "state file: ", [](const std::string& text) {
    StateFile loaded;
    std::string error;
    bool incompatible = false;
    if (!StateStore::fromJson(text, &loaded, &error, &incompatible)) {
      EXPECT_FALSE(error.empty());
      throw std::runtime_error("state file: " + error);
    }
    for (const WheelRecord& w : loaded.wheels) {
      EXPECT_TRUE(std::isfinite(w.accumulated_loss_kg) && w.accumulated_loss_kg >= 0.0) << w.accumulated_loss_kg;
      EXPECT_TRUE(std::isfinite(w.distance_m) && w.distance_m >= 0.0) << w.distance_m;
    }
  });
  EXPECT_GT(o.accepted, 0);
  EXPECT_GT(o.rejected, 0);
}

}  // namespace
}  // namespace tread_wear
