// Offline replay of drive bags: the replay equals the wear model integrated along the drive (computed here
// directly, without the estimator), does not depend on the thread count, and bad bags (missing file, truncated
// data, missing topics, wrong types) give a clear error, a non-zero exit and no summary marked complete.
#include <gtest/gtest.h>
#include <ros/time.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <iterator>

#include <nlohmann/json.hpp>

#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/io/vehicle_params_io.h"
#include "tread_wear/ros/bag/drive_bag_reader.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"
#include "tread_wear/ros/bag/replay_config.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
const std::string kConfig = kSource + "/config/vehicle_wheels.yaml";

/// 12 s: launch to 40 km/h, cruise, brake to 20 km/h; deterministic route with a junction turn or bend.
SpeedProfile shortProfile() {
  return SpeedProfile({0, 2, 6, 9, 12}, {0, 10 / 3.6, 40 / 3.6, 40 / 3.6, 20 / 3.6}, {{"A", 0, 6}, {"B", 6, 12}},
                      "short");
}

std::string tempPath(const std::string& name) { return ::testing::TempDir() + name; }

std::string writeShortDrive(const std::string& name, double rate_hz) {
  const SpeedProfile profile = shortProfile();
  RouteParams rp;
  const Route route = buildRoute(profile, rp);
  DriveOptions options;
  options.rate_hz = rate_hz;
  for (int w = 0; w < kWheelCount; ++w) options.wheel_names.push_back(wheelName(w));
  const std::string path = tempPath(name);
  writeDriveBag(path, profile, route, VehicleModel(loadVehicleParams(kSource + "/config/vehicle_passenger_car.yaml")),
                rp, options);
  return path;
}

struct RunResult {
  int exit_code;
  nlohmann::json summary;
};

RunResult runReplay(const std::string& bag, const std::string& tag, const std::string& options = "") {
  const std::string summary = tempPath(tag + "_summary.json");
  std::remove(summary.c_str());
  const std::string cmd = std::string(TREAD_WEAR_REPLAY_BINARY) + " " + bag + " --quiet --summary " + summary + " " +
                          options + " > " + tempPath(tag + ".log") + " 2>&1";
  const int status = std::system(cmd.c_str());
  RunResult r{WEXITSTATUS(status), nlohmann::json()};
  std::ifstream in(summary);
  if (in) in >> r.summary;
  return r;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string log(const std::string& tag) {
  std::ifstream in(tempPath(tag + ".log"));
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(DriveReplay, EqualsTheWearModelIntegratedAlongTheDrive) {
  ros::Time::init();
  const std::string bag = writeShortDrive("short.bag", 50.0);
  ReplayConfig config = loadReplayConfig(kConfig);
  config.settings.update_rate_hz = 50.0;  // steps on the sample times: every step sees the newest sample
  DriveReplay replay(config.settings, config.wheels);
  const DriveInfo info = readDriveBag(bag, config, &replay);
  ASSERT_TRUE(info.present);
  ASSERT_EQ(info.phases.size(), 2u);
  replay.run();
  const ReplaySummary summary = replay.summarize(info.phases, info.time_offset_s);
  ASSERT_TRUE(summary.complete) << summary.incomplete_reason;

  // Independent reference: evaluate the model at every drive sample and integrate with the trapezoid rule.
  const SpeedProfile profile = shortProfile();
  RouteParams rp;
  const Route route = buildRoute(profile, rp);
  const VehicleModel car(loadVehicleParams(kSource + "/config/vehicle_passenger_car.yaml"));
  for (int w = 0; w < kWheelCount; ++w) {
    const WearModel model(config.wheels[static_cast<std::size_t>(w)].tire, config.settings.model);
    double loss = 0.0, distance = 0.0, prev_rate = 0.0, prev_speed = 0.0, phase_a = 0.0;
    for (int k = 0; k <= 600; ++k) {
      const double t = k / 50.0;
      VehicleState s;
      car.evaluate({profile.speed(t), profile.acceleration(t), route.curvature(profile.distance(t))}, &s);
      const WheelState& ws = s.wheels[static_cast<std::size_t>(w)];
      OperatingPoint op;
      op.speed_mps = ws.speed_mps;
      op.slip_angle_rad = ws.slip_angle_rad;
      op.slip_ratio = ws.slip_ratio;
      op.path_curvature_per_m = ws.path_curvature_per_m;
      op.load_n = ws.load_n;
      WearResult r;
      model.evaluate(op, &r);
      if (k > 0) {
        const double d_loss = 0.5 * (prev_rate + r.wear_rate_kg_per_s) / 50.0;
        loss += d_loss;
        distance += 0.5 * (prev_speed + ws.speed_mps) / 50.0;
        if (t < 6.0) phase_a += d_loss;
      }
      prev_rate = r.wear_rate_kg_per_s;
      prev_speed = ws.speed_mps;
    }
    const WheelSummary& got = summary.wheels[static_cast<std::size_t>(w)];
    // Same operating points, same rule: only summation order differs (1e-12 relative).
    EXPECT_NEAR(got.mass_loss_kg, loss, 1e-12 * loss) << got.name;
    EXPECT_NEAR(got.distance_m, distance, 1e-9 * distance) << got.name;
    EXPECT_NEAR(got.phase_loss_kg[0], phase_a, 1e-12 * loss) << got.name;
    EXPECT_GT(loss, 0.0);
  }
  // Thread count does not change anything.
  config.settings.threads = 1;
  DriveReplay single(config.settings, config.wheels);
  readDriveBag(bag, config, &single);
  single.run();
  for (int w = 0; w < kWheelCount; ++w)
    EXPECT_EQ(single.records(w).back().accumulated_loss_kg, replay.records(w).back().accumulated_loss_kg);
}

TEST(DriveReplay, ToolWritesACompleteSummaryForAGoodBag) {
  ros::Time::init();
  const RunResult r = runReplay(writeShortDrive("good.bag", 50.0), "good");
  ASSERT_EQ(r.exit_code, 0) << log("good");
  EXPECT_TRUE(r.summary.at("complete").get<bool>());
  ASSERT_EQ(r.summary.at("wheels").size(), 4u);
  for (const auto& w : r.summary.at("wheels")) {
    EXPECT_GT(w.at("mass_loss_kg").get<double>(), 0.0);
    EXPECT_NEAR(w.at("mg_per_km").get<double>(),
                w.at("mass_loss_kg").get<double>() / w.at("distance_m").get<double>() * 1e9, 1e-9);
    EXPECT_TRUE(w.contains("slide_fraction_mean"));
    EXPECT_TRUE(w.contains("name"));
  }
  EXPECT_EQ(r.summary.at("phases").size(), 2u);
}

// A malformed command line is a usage error (exit 2) that names the option; nothing is replayed.
TEST(DriveReplay, BadOptionsAreUsageErrors) {
  const std::string bag = tempPath("never_read.bag");
  const std::pair<const char*, const char*> cases[] = {
      {"--threads x", "--threads must be an integer, not 'x'"},
      {"--rate-hz -50", "--rate-hz must be > 0"},
      {"--rate-hz fifty", "--rate-hz must be a number, not 'fifty'"},
      {"--preset ultra", "--preset must be fast, standard, fine or reference, not 'ultra'"},
      {"--colour red", "unknown option '--colour'"},
      {"second.bag", "unexpected argument 'second.bag'"}};
  for (const auto& [options, message] : cases) {
    const RunResult r = runReplay(bag, "usage", options);
    EXPECT_EQ(r.exit_code, 2) << options;
    EXPECT_NE(log("usage").find(message), std::string::npos) << log("usage");
  }
}

TEST(DriveReplay, MissingFileFails) {
  const RunResult r = runReplay(tempPath("does_not_exist.bag"), "missing");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(r.summary.at("complete").get<bool>());
  EXPECT_NE(log("missing").find("cannot open the bag"), std::string::npos) << log("missing");
  // A directory opens as a stream but has no file size: the same error, not an allocation of its "size".
  const RunResult dir = runReplay(::testing::TempDir(), "directory");
  EXPECT_EQ(dir.exit_code, 1);
  EXPECT_NE(log("directory").find("cannot open the bag (missing or unreadable file)"), std::string::npos)
      << log("directory");
}

TEST(DriveReplay, TruncatedBagFails) {
  ros::Time::init();
  const std::string bytes = fileBytes(writeShortDrive("to_truncate.bag", 50.0));
  const std::string cut = tempPath("truncated.bag");
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const RunResult r = runReplay(cut, "truncated");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(r.summary.at("complete").get<bool>());
  EXPECT_NE(log("truncated").find("not a readable bag"), std::string::npos) << log("truncated");
}

/// The messages of `source` written again with chunks of about `threshold_bytes`, compressed or not: the same data,
/// in many chunks each followed by its index records (rosbag's default threshold of 768 KB puts a short drive in one
/// chunk).
std::string rechunk(const std::string& source, const std::string& name, std::uint32_t threshold_bytes,
                    rosbag::compression::CompressionType compression) {
  rosbag::Bag in(source, rosbag::bagmode::Read), out(tempPath(name), rosbag::bagmode::Write);
  out.setChunkThreshold(threshold_bytes);
  out.setCompression(compression);
  for (const rosbag::MessageInstance& m : rosbag::View(in))
    out.write(m.getTopic(), m.getTime(), m, m.getConnectionHeader());
  return tempPath(name);
}

/// Chunks of a bag, counted by their header field "compression=NAME" (each chunk record has one).
int chunkCount(const std::string& bytes, const std::string& compression = "none") {
  const std::string field = "compression=" + compression;
  int n = 0;
  for (auto at = bytes.find(field); at != std::string::npos; at = bytes.find(field, at + 1)) ++n;
  return n;
}

struct MutantOutcomes {
  int read = 0, rejected = 0, rejected_by_chunk_check = 0, refused_span = 0;
};

/// Writes `count` mutants of `bytes` (seeded; 1-8 bytes overwritten each) to `path` and reads and replays each:
/// a rejection must name the file, a refused replay the span limit; anything else (a crash) fails the test.
MutantOutcomes replayMutants(const std::string& bytes, const std::string& path, unsigned seed, int count) {
  std::mt19937 rng(seed);
  MutantOutcomes out;
  for (int mutant = 0; mutant < count; ++mutant) {
    std::string m = bytes;
    const int edits = 1 + static_cast<int>(rng() % 8);
    for (int e = 0; e < edits; ++e) m[rng() % m.size()] = static_cast<char>(rng() % 256);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << m;
    ReplayConfig config = loadReplayConfig(kConfig);
    DriveReplay replay(config.settings, config.wheels);
    try {
      readDriveBag(path, config, &replay);
    } catch (const BagError& e) {
      ++out.rejected;
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << "mutant " << mutant << ": " << what;
      if (what.find("bag data unreadable (corrupt): ") != std::string::npos) ++out.rejected_by_chunk_check;
      continue;
    }
    ++out.read;
    try {  // a corrupt time stamp can make the span absurd: refused before anything is allocated for it
      replay.run();
    } catch (const std::runtime_error& e) {
      ++out.refused_span;
      EXPECT_NE(std::string(e.what()).find("more than max_span_s"), std::string::npos) << e.what();
    }
  }
  return out;
}

// Bytes overwritten anywhere in a bag: every mutant is read and replayed, or rejected with an error that names the
// file or the problem, never a crash. rosbag reads the records inside a chunk without bounds checks, so a corrupt
// length there made it read past its buffer (segmentation fault in 2 of 80 such mutants before checkBagRecords),
// and a corrupt time stamp made the replay allocate step records for billions of seconds (std::bad_alloc in a
// worker thread: abort); both checks must reject some of these mutants.
TEST(DriveReplay, OverwrittenBytesAreReadOrRejectedNeverACrash) {
  ros::Time::init();
  const std::string bytes = fileBytes(writeShortDrive("to_corrupt.bag", 10.0));
  ASSERT_EQ(chunkCount(bytes), 1);
  const MutantOutcomes out = replayMutants(bytes, tempPath("corrupt.bag"), 7, 300);
  EXPECT_GT(out.read, 0);
  EXPECT_GT(out.rejected_by_chunk_check, 0) << "of " << out.rejected << " rejected";
  EXPECT_GT(out.refused_span, 0) << "of " << out.read << " read";
}

// checkBagRecords walks the file a record at a time and decompresses bz2 and lz4 chunks before rosbag parses them:
// the same drive in dozens of chunks, each followed by its index records, uncompressed or compressed, passes the
// check and replays to the same losses as in one chunk. Its mutants, with corrupt bytes in any chunk or index, are
// read or rejected, never a crash (before the compressed chunks were checked, 19 of 1200 such mutants of the
// compressed bags crashed rosbag with a segmentation fault).
TEST(DriveReplay, ManyChunksReadAsOneAndTheirMutantsNeverCrash) {
  ros::Time::init();
  const std::string one = writeShortDrive("one_chunk.bag", 10.0);
  ReplayConfig config = loadReplayConfig(kConfig);
  DriveReplay from_one(config.settings, config.wheels);
  readDriveBag(one, config, &from_one);
  from_one.run();
  const std::pair<rosbag::compression::CompressionType, std::string> codecs[] = {
      {rosbag::compression::Uncompressed, "none"}, {rosbag::compression::BZ2, "bz2"}, {rosbag::compression::LZ4, "lz4"}};
  unsigned seed = 11;
  for (const auto& [codec, name] : codecs) {
    SCOPED_TRACE(name);
    const std::string many = rechunk(one, "many_chunks_" + name + ".bag", 4096, codec);
    ASSERT_GE(chunkCount(fileBytes(many), name), 20);
    DriveReplay from_many(config.settings, config.wheels);
    readDriveBag(many, config, &from_many);
    from_many.run();
    for (int w = 0; w < kWheelCount; ++w) {
      EXPECT_GT(from_one.records(w).back().accumulated_loss_kg, 0.0);
      EXPECT_EQ(from_many.sampleCount(w), from_one.sampleCount(w));
      EXPECT_EQ(from_many.records(w).back().accumulated_loss_kg, from_one.records(w).back().accumulated_loss_kg);
    }
    const MutantOutcomes out = replayMutants(fileBytes(many), tempPath("corrupt_" + name + ".bag"), seed++, 150);
    EXPECT_GT(out.read, 0);
    EXPECT_GT(out.rejected_by_chunk_check, 0) << "of " << out.rejected << " rejected";
  }
}

// One sample at 1e9 s, 30 years after the others (a corrupt time stamp), would ask for 1e11 step records per wheel:
// run() refuses the span and names the gap (1e9 - 1001 s after the last good sample).
TEST(DriveReplay, SpanBeyondTheLimitIsRefusedBeforeAllocation) {
  ReplayConfig config = loadReplayConfig(kConfig);
  config.settings.threads = 2;
  DriveReplay replay(config.settings, config.wheels);
  InputSample sample;
  for (int w = 0; w < replay.wheelCount(); ++w) {
    for (int k = 0; k <= 10; ++k) {
      sample.t_s = 1000.0 + 0.1 * k;
      for (const InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed}) {
        sample.kind = kind;
        sample.value[0] = kind == InputKind::kLoad ? 3000.0 : kind == InputKind::kSpeed ? 10.0 : 0.0;
        replay.addSample(w, sample);
      }
    }
  }
  sample.t_s = 1e9;
  sample.kind = InputKind::kSpeed;
  sample.value[0] = 10.0;
  replay.addSample(0, sample);
  try {
    replay.run();
    FAIL() << "a span of 1e9 s was replayed";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("more than max_span_s = 21600 s"), std::string::npos) << what;
    EXPECT_NE(what.find("largest gap between a wheel's samples is 9.99999e+08 s after t = 1001 s"), std::string::npos)
        << what;
  }
  std::string error;
  ReplaySettings bad = config.settings;
  bad.max_span_s = 0.0;
  EXPECT_FALSE(bad.validate(&error));
  EXPECT_NE(error.find("max_span_s = 0"), std::string::npos) << error;
}

TEST(DriveReplay, MissingTopicAndWrongTypeFail) {
  ros::Time::init();
  const std::string path = tempPath("partial.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    WheelLoad load;
    WheelSlip slip;
    WheelSpeed speed;
    load.load_n = 3000.0;
    speed.speed_mps = 10.0;
    for (int k = 1; k <= 50; ++k) {
      const ros::Time t(1000.0 + k * 0.02);
      for (const char* name : {"front_left", "front_right", "rear_left", "rear_right"}) {
        bag.write(std::string("/wheels/") + name + "/load", t, load);
        bag.write(std::string("/wheels/") + name + "/slip", t, slip);
        if (std::string(name) != "rear_right") bag.write(std::string("/wheels/") + name + "/speed", t, speed);
      }
    }
  }
  RunResult r = runReplay(path, "missing_topic");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(r.summary.at("complete").get<bool>());
  EXPECT_NE(log("missing_topic").find("missing topic /wheels/rear_right/speed"), std::string::npos)
      << log("missing_topic");

  {
    rosbag::Bag bag(path, rosbag::bagmode::Append);
    std_msgs::String text;
    bag.write("/wheels/rear_right/speed", ros::Time(1000.02), text);
  }
  r = runReplay(path, "wrong_type");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(r.summary.at("complete").get<bool>());
  EXPECT_NE(log("wrong_type").find("has type std_msgs/String, expected tread_wear/WheelSpeed"), std::string::npos)
      << log("wrong_type");
}

TEST(DriveReplay, GapsMakeTheSummaryIncomplete) {
  // A bag whose wheels stop sending half-way: the replay finishes but must not claim completeness.
  ros::Time::init();
  ReplayConfig config = loadReplayConfig(kConfig);
  DriveReplay replay(config.settings, config.wheels);
  for (int w = 0; w < replay.wheelCount(); ++w) {
    for (int k = 0; k <= 100; ++k) {
      const double t = 1000.0 + k * 0.02;
      if (w == 0 && k > 50) break;
      for (InputKind kind : {InputKind::kLoad, InputKind::kSlip, InputKind::kSpeed}) {
        InputSample s;
        s.t_s = t;
        s.kind = kind;
        s.value[0] = kind == InputKind::kLoad ? 3000.0 : kind == InputKind::kSpeed ? 10.0 : 0.0;
        replay.addSample(w, s);
      }
    }
  }
  replay.run();
  const ReplaySummary s = replay.summarize({});
  EXPECT_FALSE(s.complete);
  EXPECT_NE(s.incomplete_reason.find(config.wheels[0].name), std::string::npos) << s.incomplete_reason;
}

}  // namespace
}  // namespace tread_wear
