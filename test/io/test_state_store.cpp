// StateStore: exact round trip, atomic replacement, and bad files reported and moved aside, never zeroed.
#include <gtest/gtest.h>

#include <dirent.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tread_wear/io/state_store.h"

namespace tread_wear {
namespace {

class StateStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/tread_wear_state_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
    path_ = dir_ + "/state.json";
  }
  void TearDown() override {
    for (const std::string& f : files()) std::remove((dir_ + "/" + f).c_str());
    rmdir(dir_.c_str());
  }
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    DIR* d = opendir(dir_.c_str());
    while (dirent* e = readdir(d)) {
      const std::string n = e->d_name;
      if (n != "." && n != "..") out.push_back(n);
    }
    closedir(d);
    return out;
  }
  void write(const std::string& text) { std::ofstream(path_) << text; }
  std::string read(const std::string& path) const {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  StateFile sample() const {
    StateFile s;
    s.wheels.push_back({"front_left", "tire-A1", 1.234567890123456789e-3, 12345.678901234567, 1.7e9});
    s.wheels.push_back({"rear_right", "tire-B2", 0.1 + 0.2, 1.0 / 3.0, 0.0});
    return s;
  }
  std::string dir_, path_;
};

TEST_F(StateStoreTest, MissingFileIsAnEmptyState) {
  const LoadResult r = StateStore(path_).load();
  EXPECT_EQ(r.status, LoadStatus::kMissing);
  EXPECT_TRUE(r.state.wheels.empty());
}

TEST_F(StateStoreTest, RoundTripIsExact) {
  StateStore store(path_);
  std::string error;
  ASSERT_TRUE(store.save(sample(), &error)) << error;
  const LoadResult r = store.load();
  ASSERT_EQ(r.status, LoadStatus::kLoaded) << r.message;
  ASSERT_EQ(r.state.wheels.size(), 2u);
  for (const WheelRecord& w : sample().wheels) {
    const WheelRecord* got = r.state.find(w.name);
    ASSERT_NE(got, nullptr);
    EXPECT_EQ(got->tire_id, w.tire_id);
    EXPECT_EQ(got->accumulated_loss_kg, w.accumulated_loss_kg);  // bit-exact: nothing is lost on restart
    EXPECT_EQ(got->distance_m, w.distance_m);
    EXPECT_EQ(got->reset_unix_s, w.reset_unix_s);
  }
  EXPECT_GT(r.state.saved_unix_s, 1.6e9);
  // Only the state file remains: the temporary was renamed over it.
  EXPECT_EQ(files(), std::vector<std::string>{"state.json"});
}

TEST_F(StateStoreTest, SaveReplacesAnExistingFile) {
  StateStore store(path_);
  std::string error;
  ASSERT_TRUE(store.save(sample(), &error));
  StateFile s = sample();
  s.wheels[0].accumulated_loss_kg = 2.0;
  ASSERT_TRUE(store.save(s, &error));
  EXPECT_EQ(store.load().state.find("front_left")->accumulated_loss_kg, 2.0);
}

TEST_F(StateStoreTest, LeftoverTemporaryFromACrashDoesNotMatter) {
  StateStore store(path_);
  std::string error;
  ASSERT_TRUE(store.save(sample(), &error));
  std::ofstream(path_ + ".tmp") << "{\"format\": \"tread_wear_state\", \"vers";  // crash mid-write
  const LoadResult r = store.load();
  EXPECT_EQ(r.status, LoadStatus::kLoaded);
  EXPECT_EQ(r.state.wheels.size(), 2u);
  ASSERT_TRUE(store.save(sample(), &error)) << error;  // truncates and reuses the temporary
}

TEST_F(StateStoreTest, TruncatedFileIsReportedAndMovedAside) {
  const std::string good = StateStore::toJson(sample());
  const std::string truncated = good.substr(0, good.size() / 2);
  write(truncated);
  const LoadResult r = StateStore(path_).load();
  EXPECT_EQ(r.status, LoadStatus::kCorrupt);
  EXPECT_NE(r.message.find("not valid JSON"), std::string::npos) << r.message;
  EXPECT_TRUE(r.state.wheels.empty());
  ASSERT_FALSE(r.moved_to.empty());
  EXPECT_NE(r.moved_to.find(path_ + ".corrupt-"), std::string::npos);
  EXPECT_EQ(read(r.moved_to), truncated);  // kept byte for byte for recovery
  EXPECT_NE(access(path_.c_str(), F_OK), 0);
}

TEST_F(StateStoreTest, InvalidValuesAreCorrupt) {
  write(R"({"format": "tread_wear_state", "version": 1, "saved_unix_s": 0, "wheels": [
           {"name": "fl", "tire_id": "x", "accumulated_loss_kg": -1.0, "distance_m": 0}]})");
  LoadResult r = StateStore(path_).load();
  EXPECT_EQ(r.status, LoadStatus::kCorrupt);
  EXPECT_NE(r.message.find("accumulated_loss_kg"), std::string::npos) << r.message;
  write(R"({"format": "tread_wear_state", "version": 1, "saved_unix_s": 0, "wheels": [
           {"name": "fl", "tire_id": "x", "accumulated_loss_kg": 0.1}]})");
  r = StateStore(path_).load();
  EXPECT_EQ(r.status, LoadStatus::kCorrupt);
  EXPECT_NE(r.message.find("distance_m"), std::string::npos) << r.message;
  write(R"({"format": "tread_wear_state", "version": 1, "saved_unix_s": 0, "wheels": [
           {"name": "fl", "tire_id": "x", "accumulated_loss_kg": 0.1, "distance_m": 1},
           {"name": "fl", "tire_id": "y", "accumulated_loss_kg": 0.1, "distance_m": 1}]})");
  r = StateStore(path_).load();
  EXPECT_EQ(r.status, LoadStatus::kCorrupt);
  EXPECT_NE(r.message.find("twice"), std::string::npos) << r.message;
}

TEST_F(StateStoreTest, OtherVersionOrFormatIsIncompatible) {
  write(R"({"format": "tread_wear_state", "version": 2, "saved_unix_s": 0, "wheels": []})");
  LoadResult r = StateStore(path_).load();
  EXPECT_EQ(r.status, LoadStatus::kIncompatible);
  EXPECT_NE(r.message.find("version 2"), std::string::npos) << r.message;
  EXPECT_NE(r.moved_to.find(".incompatible-"), std::string::npos);
  write(R"({"something": "else"})");
  r = StateStore(path_).load();
  EXPECT_EQ(r.status, LoadStatus::kIncompatible);
}

TEST_F(StateStoreTest, UnwritableDirectoryFailsWithTheStep) {
  StateStore store("/nonexistent_dir_for_tread_wear/state.json");
  std::string error;
  EXPECT_FALSE(store.save(sample(), &error));
  EXPECT_NE(error.find("open"), std::string::npos) << error;
}

}  // namespace
}  // namespace tread_wear
