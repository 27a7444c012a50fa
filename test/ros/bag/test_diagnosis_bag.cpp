// The diagnosis' rosbag adapter (include/tread_wear/ros/bag/diagnosis_bag.h): segments between mass checkpoints become runs
// with time-weighted means computed by hand here, messages stamped at a checkpoint go to the segment that starts
// there, malformed bags get errors naming the bag and the problem, and the documented example bag
// (examples/diagnosis/make_bag.py) gives back the run table it was written from and the same verdict.
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int32.h>
#include <std_msgs/String.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "tread_wear/TreadTemperature.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/cli/diagnose_cli.h"
#include "tread_wear/io/params_io.h"
#include "tread_wear/ros/bag/diagnosis_bag.h"

namespace tread_wear {
namespace diagnosis {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
constexpr double kT0 = 1000.0;  // bag time of the first checkpoint [s]

/// Writes the messages of one wheel ("fl") of a diagnosis bag.
class DiagnosisBagWriter {
 public:
  explicit DiagnosisBagWriter(const std::string& name) : path_(::testing::TempDir() + name) {
    bag_.open(path_, rosbag::bagmode::Write);
  }
  void inputs(double t, double speed_mps, double slip_angle_rad, double load_n, double temperature_c) {
    speed(t, speed_mps);
    WheelSlip s;
    s.slip_angle_rad = slip_angle_rad;
    s.slip_ratio = 0.01;
    s.path_curvature_per_m = 1.0 / 0.06;
    write("slip", t, s);
    load(t, load_n);
    TreadTemperature temp;
    temp.temperature_c = temperature_c;
    write("tread_temperature", t, temp);
  }
  void load(double t, double load_n) {
    WheelLoad l;
    l.load_n = load_n;
    write("load", t, l);
  }
  void speed(double t, double speed_mps) {
    WheelSpeed v;
    v.speed_mps = speed_mps;
    write("speed", t, v);
  }
  void sideForce(double t, double fy_n) {
    geometry_msgs::WrenchStamped w;
    w.wrench.force.y = fy_n;
    write("measured/side_force", t, w);
  }
  void mass(double t, double kg) {
    std_msgs::Float64 m;
    m.data = kg;
    write("measured/mass", t, m);
  }
  void treadDepth(double t, double m) {
    std_msgs::Float64 d;
    d.data = m;
    write("measured/tread_depth", t, d);
  }
  void cycle(double t, int id) {
    std_msgs::Int32 c;
    c.data = id;
    write("measured/cycle", t, c);
  }
  /// A bag-wide recorded covariate, "name=value" (measured/covariate).
  void covariate(double t, const std::string& text) {
    std_msgs::String c;
    c.data = text;
    bag_.write("measured/covariate", ros::Time(t), c);
  }
  const std::string& close() {
    bag_.close();
    return path_;
  }

 private:
  template <class M>
  void write(const std::string& topic, double t, const M& msg) {
    bag_.write("wheels/fl/" + topic, ros::Time(t), msg);
  }
  std::string path_;
  rosbag::Bag bag_;
};

const TireParams& rigTire() {
  static const TireParams tire = loadTireParams(kSource + "/config/tires/grosch_wheel.yaml");
  return tire;
}

/// The replay's rules with inputs held for `timeout_s` (the tests' bags have sparse messages).
ReplaySettings heldInputs(double timeout_s) {
  ReplaySettings r;
  r.estimator.stale_timeout_s = timeout_s;
  r.estimator.max_step_s = 2.0 * timeout_s;
  return r;
}

std::string errorOf(const std::string& bag_path) {
  try {
    readDiagnosisBag(bag_path, rigTire(), ReplaySettings());
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// The means are trapezoid means on the replay's 100 Hz grid from the first input (t = 1000 s): an input that
// changes at a grid time t_c counts from t_c - 5 ms (the interval ending at t_c averages its two ends), and the
// inputs written at a checkpoint are the last step of the segment that ends there, with weight 5 ms.
TEST(DiagnosisBag, SegmentsBecomeRunsWithTrapezoidMeansOnTheReplayGrid) {
  DiagnosisBagWriter w("diagnosis_two_segments.bag");
  // Segment 1, (1000, 1010]: 2 m/s; the load alternates 73 / 77 N every second; side force samples 50 and 52 N;
  // 40 degC.
  w.mass(kT0, 0.100);
  w.cycle(kT0, 1);
  w.inputs(kT0, 2.0, -0.17, 73.0, 40.0);
  for (int k = 1; k < 10; ++k) w.load(kT0 + k, k % 2 ? 77.0 : 73.0);
  w.sideForce(kT0 + 3.0, 50.0);
  w.sideForce(kT0 + 7.0, 52.0);
  // Checkpoint at 1010: 3 mg lost. The cycle message and the side force stamped there belong to segment 2.
  w.mass(kT0 + 10.0, 0.100 - 3e-6);
  w.cycle(kT0 + 10.0, 2);
  w.sideForce(kT0 + 10.0, 60.0);
  // Segment 2, (1010, 1020]: 1 m/s until 1014, then 3 m/s; load 100 N; 50 degC; 4 mg lost.
  w.inputs(kT0 + 10.0, 1.0, -0.09, 100.0, 50.0);
  w.speed(kT0 + 14.0, 3.0);
  w.sideForce(kT0 + 15.0, 62.0);
  w.mass(kT0 + 20.0, 0.100 - 7e-6);
  const RunTable t = readDiagnosisBag(w.close(), rigTire(), heldInputs(20.0));

  ASSERT_EQ(t.runs.size(), 2u);
  const double h = 0.005;  // half a grid step [s]
  const RunRecord& a = t.runs[0];
  // Segment 1: the step at 1010 sees segment 2's inputs (1 m/s, 100 N, 0.09 rad, 50 degC) with weight h.
  EXPECT_NEAR(a.op.speed_mps, (2.0 * (10.0 - h) + 1.0 * h) / 10.0, 1e-12);
  EXPECT_NEAR(a.op.slip_angle_rad, (0.17 * (10.0 - h) + 0.09 * h) / 10.0, 1e-12);  // mean |alpha|
  EXPECT_NEAR(a.op.slip_ratio, 0.01, 1e-12);
  EXPECT_NEAR(a.op.path_curvature_per_m, 1.0 / 0.06, 1e-9);
  // Load: 73 N on (1000, 1001 - h], then 77 and 73 in turn for 1 s each (77 on odd seconds), 77 N up to
  // 1010 - h, 100 N for h.
  const double load_sum = 73.0 * (1.0 - h) + 5 * 77.0 + 4 * 73.0 + 100.0 * h;
  const double load2_sum = 73.0 * 73.0 * (1.0 - h) + 5 * 77.0 * 77.0 + 4 * 73.0 * 73.0 + 1e4 * h;
  EXPECT_NEAR(a.op.load_n, load_sum / 10.0, 1e-9);
  EXPECT_NEAR(a.load_std_n, std::sqrt(load2_sum / 10.0 - std::pow(load_sum / 10.0, 2)), 1e-6);
  EXPECT_NEAR(a.op.tread_temperature_c, (40.0 * (10.0 - h) + 50.0 * h) / 10.0, 1e-12);
  EXPECT_NEAR(a.measured_side_force_n, 51.0, 1e-12);
  EXPECT_NEAR(a.drive_distance_m, 2.0 * (10.0 - h) + 1.0 * h, 1e-9);
  EXPECT_NEAR(a.drive_time_s, 10.0, 1e-9);
  EXPECT_NEAR(a.measured_wear_rate_kg_per_m, 3e-6 / a.drive_distance_m, 1e-18);
  EXPECT_EQ(a.cycle_id, 1);
  EXPECT_EQ(a.run_order, 1);

  const RunRecord& b = t.runs[1];
  const double distance_b = 1.0 * (4.0 - h) + 3.0 * (6.0 + h);
  EXPECT_NEAR(b.op.speed_mps, distance_b / 10.0, 1e-12);
  EXPECT_NEAR(b.op.load_n, 100.0, 1e-9);
  EXPECT_NEAR(b.load_std_n, 0.0, 1e-4);
  EXPECT_NEAR(b.measured_side_force_n, 61.0, 1e-12);
  EXPECT_NEAR(b.drive_distance_m, distance_b, 1e-9);
  EXPECT_NEAR(b.measured_wear_rate_kg_per_m, 4e-6 / distance_b, 1e-18);
  EXPECT_EQ(b.cycle_id, 2);
  EXPECT_EQ(b.run_order, 2);
  ASSERT_EQ(t.covariate_names, (std::vector<std::string>{"distance_m", "duration_s", "mass_loss_kg"}));
  EXPECT_NEAR(b.covariates[0], distance_b, 1e-9);
  EXPECT_NEAR(b.covariates[1], 10.0, 1e-9);
  EXPECT_NEAR(b.covariates[2], 4e-6, 1e-15);
  EXPECT_EQ(b.text_covariates, std::vector<std::string>{"fl"});

  // The points keep the integrals: their distance weights sum to the integrated distance (no zero load here), and
  // the points of segment 2 are its two speeds (one cell each: the other inputs are constant).
  double d = 0.0;
  for (const WeightedOperatingPoint& p : b.drive_points) d += p.distance_m;
  EXPECT_NEAR(d, distance_b, 1e-9);
  ASSERT_EQ(b.drive_points.size(), 2u);
}

// Recorded covariates (measured/covariate, "name=value"): each segment gets the value in effect before its end, a
// message stamped at a checkpoint opens the next segment (as the cycle), "unknown" before the first; a message that
// is not name=value is an error naming it.
TEST(DiagnosisBag, RecordedCovariatesBecomeTextCovariatesPerSegment) {
  DiagnosisBagWriter w("diagnosis_covariates.bag");
  w.mass(kT0, 0.100);
  w.covariate(kT0, "test=Run-in");
  w.inputs(kT0, 2.0, -0.17, 73.0, 40.0);
  w.covariate(kT0 + 5.0, "brand=Michelin");  // within segment 1
  w.mass(kT0 + 10.0, 0.100 - 3e-6);
  w.covariate(kT0 + 10.0, "test=Rural");  // at the checkpoint: segment 2
  w.inputs(kT0 + 15.0, 2.0, -0.17, 73.0, 40.0);
  w.mass(kT0 + 20.0, 0.100 - 5e-6);
  w.covariate(kT0 + 20.0, "test=Urban");  // at the last checkpoint: no segment follows
  w.inputs(kT0 + 20.0, 2.0, -0.17, 73.0, 40.0);
  const RunTable t = readDiagnosisBag(w.close(), rigTire(), heldInputs(10.0));
  ASSERT_EQ(t.runs.size(), 2u);
  EXPECT_EQ(t.text_covariate_names, (std::vector<std::string>{"wheel", "test", "brand"}));
  EXPECT_EQ(t.runs[0].text_covariates, (std::vector<std::string>{"fl", "Run-in", "Michelin"}));
  EXPECT_EQ(t.runs[1].text_covariates, (std::vector<std::string>{"fl", "Rural", "Michelin"}));

  DiagnosisBagWriter bad("diagnosis_covariate_bad.bag");
  bad.mass(kT0, 0.100);
  bad.covariate(kT0, "Run-in");
  bad.inputs(kT0, 2.0, -0.17, 73.0, 40.0);
  bad.mass(kT0 + 10.0, 0.100 - 3e-6);
  bad.inputs(kT0 + 10.0, 2.0, -0.17, 73.0, 40.0);
  const std::string e = errorOf(bad.close());
  EXPECT_NE(e.find("measured/covariate"), std::string::npos) << e;
  EXPECT_NE(e.find("'Run-in' is not name=value"), std::string::npos) << e;
}

// A tread-depth gauge instead of a scale: the loss is the depth difference times the mass of a uniform tread layer
// per unit depth, rho w 2 pi R (the Grosch wheel: 1150 kg/m^3, 18 mm, 36 mm). Inputs at 10 Hz, the node's timeout.
TEST(DiagnosisBag, TreadDepthCheckpointsGiveTheLossOfTheirLayer) {
  DiagnosisBagWriter w("diagnosis_tread_depth.bag");
  w.treadDepth(kT0, 6.0e-3);
  for (int k = 0; k <= 100; ++k) w.inputs(kT0 + 0.1 * k, 2.0, -0.17, 75.0, 40.0);
  w.treadDepth(kT0 + 10.0, 6.0e-3 - 2e-6);
  const RunTable t = readDiagnosisBag(w.close(), rigTire(), ReplaySettings());
  ASSERT_EQ(t.runs.size(), 1u);
  const double layer_kg_per_m = 1150.0 * 18e-3 * 2.0 * M_PI * 36e-3;
  EXPECT_NEAR(t.runs[0].covariates[2], 2e-6 * layer_kg_per_m, 1e-15);
  EXPECT_NEAR(t.runs[0].drive_distance_m, 20.0, 1e-9);
  EXPECT_NEAR(t.runs[0].measured_wear_rate_kg_per_m, 2e-6 * layer_kg_per_m / 20.0, 1e-15);

  DiagnosisBagWriter deeper("diagnosis_tread_deeper.bag");
  deeper.treadDepth(kT0, 6.0e-3);
  for (int k = 0; k <= 100; ++k) deeper.inputs(kT0 + 0.1 * k, 2.0, -0.17, 75.0, 40.0);
  deeper.treadDepth(kT0 + 10.0, 6.0e-3 + 1e-6);
  EXPECT_NE(errorOf(deeper.close()).find("the tread depth did not decrease"), std::string::npos);
}

TEST(DiagnosisBag, MalformedBagsNameTheProblem) {
  EXPECT_NE(errorOf("/nonexistent/drive.bag").find("/nonexistent/drive.bag: cannot open the bag"), std::string::npos);

  DiagnosisBagWriter no_mass("diagnosis_no_mass.bag");
  no_mass.inputs(kT0, 2.0, -0.17, 75.0, 40.0);
  EXPECT_NE(errorOf(no_mass.close()).find("no topic wheels/<name>/measured/mass"), std::string::npos);

  DiagnosisBagWriter one_checkpoint("diagnosis_one_checkpoint.bag");
  one_checkpoint.mass(kT0, 0.1);
  one_checkpoint.inputs(kT0, 2.0, -0.17, 75.0, 40.0);
  EXPECT_NE(errorOf(one_checkpoint.close()).find("fewer than two mass checkpoints"), std::string::npos);

  DiagnosisBagWriter gain("diagnosis_mass_gain.bag");
  gain.mass(kT0, 0.1);
  gain.inputs(kT0, 2.0, -0.17, 75.0, 40.0);
  gain.mass(kT0 + 10.0, 0.1 + 1e-6);
  const std::string gain_error = errorOf(gain.close());
  EXPECT_NE(gain_error.find("segment 1"), std::string::npos) << gain_error;
  EXPECT_NE(gain_error.find("the mass did not decrease"), std::string::npos) << gain_error;

  DiagnosisBagWriter standstill("diagnosis_standstill.bag");
  standstill.mass(kT0, 0.1);
  standstill.inputs(kT0, 0.0, -0.17, 75.0, 40.0);
  standstill.mass(kT0 + 10.0, 0.1 - 1e-6);
  EXPECT_NE(errorOf(standstill.close()).find("no motion"), std::string::npos);

  // A record inside a chunk whose header length runs past the chunk (rosbag would read past its buffer): the
  // first record of the first chunk, whose data start after the chunk header's last field, size=<uint32>, and the
  // record's data length (rosbag 2.0 writes the header fields in name order: compression, op, size).
  DiagnosisBagWriter corrupt("diagnosis_corrupt_chunk.bag");
  corrupt.mass(kT0, 0.1);
  corrupt.inputs(kT0, 2.0, -0.17, 75.0, 40.0);
  corrupt.mass(kT0 + 10.0, 0.1 - 1e-6);
  const std::string corrupt_path = corrupt.close();
  {
    std::fstream f(corrupt_path, std::ios::in | std::ios::out | std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(f)), {});
    const std::size_t size_field = bytes.find("size=", bytes.find("compression=none"));
    ASSERT_NE(size_field, std::string::npos);
    f.seekp(static_cast<std::streamoff>(size_field + 5 + 4 + 4));
    f.write("\xff\xff\xff\x7f", 4);
  }
  const std::string corrupt_error = errorOf(corrupt_path);
  EXPECT_NE(corrupt_error.find(corrupt_path + ": bag data unreadable (corrupt): record header of 2147483647 bytes past "
                               "the end of its chunk"),
            std::string::npos)
      << corrupt_error;

  DiagnosisBagWriter no_load("diagnosis_no_load.bag");
  no_load.mass(kT0, 0.1);
  no_load.speed(kT0, 2.0);
  no_load.mass(kT0 + 10.0, 0.1 - 1e-6);
  EXPECT_NE(errorOf(no_load.close()).find("missing input topic wheels/fl/load of wheel fl"), std::string::npos);
}

// examples/diagnosis/README.md: the example run table written as a bag by make_bag.py (each run a steady segment,
// the load alternating +-2 N) reads back as the same runs, and tread_wear_diagnose --bag gives the verdict of the
// run table.
TEST(DiagnosisBag, DocumentedExampleBagGivesBackTheRunTable) {
  const std::string runs_path = kSource + "/examples/diagnosis/polishing_runs.csv";
  const std::string bag_path = ::testing::TempDir() + "diagnosis_polishing.bag";
  std::remove(bag_path.c_str());
  const std::string command = "PYTHONPATH=" + std::string(TREAD_WEAR_PYTHON_PATH) + " /usr/bin/python3 " + kSource +
                              "/examples/diagnosis/make_bag.py " + runs_path + " " + bag_path;
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const RunTable from_csv = readRunTable(runs_path);
  // make_bag.py writes a sample every tenth of a run (45-90 s): hold inputs for 100 s.
  const RunTable from_bag = readDiagnosisBag(bag_path, rigTire(), heldInputs(100.0));
  ASSERT_EQ(from_bag.runs.size(), from_csv.runs.size());
  for (std::size_t i = 0; i < from_csv.runs.size(); ++i) {
    const RunRecord& c = from_csv.runs[i];
    const RunRecord& b = from_bag.runs[i];
    // The bag's means differ from the table's only by the trapezoid's half step (5 ms) at each input change and
    // at the checkpoint, where the next run's inputs enter: at most 5 ms x (change) / (450 s or more).
    EXPECT_NEAR(b.op.speed_mps, c.op.speed_mps, 1e-4) << i;
    EXPECT_NEAR(b.op.slip_angle_rad, std::abs(c.op.slip_angle_rad), 1e-5) << i;
    EXPECT_NEAR(b.op.path_curvature_per_m, std::abs(c.op.path_curvature_per_m), 1e-3) << i;
    EXPECT_NEAR(b.op.load_n, c.op.load_n, 1e-3) << i;
    EXPECT_NEAR(b.load_std_n, 2.0, 0.01) << i;
    EXPECT_NEAR(b.op.tread_temperature_c, c.op.tread_temperature_c, 1e-3) << i;
    EXPECT_NEAR(b.measured_side_force_n, c.measured_side_force_n, 1e-9) << i;
    EXPECT_NEAR(b.measured_wear_rate_kg_per_m / c.measured_wear_rate_kg_per_m, 1.0, 1e-4) << i;
    EXPECT_EQ(b.cycle_id, c.cycle_id) << i;
  }

  auto diagnose = [](const std::string& input_flag, const std::string& input, const std::string& report) {
    const std::string params = kSource + "/config/tires/grosch_wheel.yaml";
    const std::string dir = ::testing::TempDir() + report;
    const char* argv[] = {"tread_wear_diagnose", "--params",  params.c_str(),     input_flag.c_str(), input.c_str(),
                          "--report",            dir.c_str(), "--no-plots",       "--input-timeout-s", "100"};
    std::ostringstream out, err;
    EXPECT_EQ(runDiagnoseCli(10, argv, readDiagnosisBag, "", out, err), 0) << err.str();
    return out.str();
  };
  const std::string verdict = "explanation: surface_polishing\n";
  EXPECT_NE(diagnose("--runs", runs_path, "diagnosis_polishing_csv").find(verdict), std::string::npos);
  EXPECT_NE(diagnose("--bag", bag_path, "diagnosis_polishing_bag").find(verdict), std::string::npos);
}

}  // namespace
}  // namespace diagnosis
}  // namespace tread_wear
