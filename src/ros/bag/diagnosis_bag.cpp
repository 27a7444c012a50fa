#include "tread_wear/ros/bag/diagnosis_bag.h"

#include <geometry_msgs/WrenchStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int32.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <tuple>

#include "tread_wear/diagnosis/parallel_for.h"
#include "tread_wear/estimation/drive_segments.h"
#include "tread_wear/ros/bag/bag_check.h"
#include "tread_wear/ros/bag/drive_bag_reader.h"

namespace tread_wear {
namespace diagnosis {
namespace {

std::string withoutLeadingSlash(const std::string& topic) {
  return !topic.empty() && topic[0] == '/' ? topic.substr(1) : topic;
}

/// What one wheel's measurement topics hold.
struct WheelRecord {
  std::string name;
  bool by_mass = false;                            ///< masses, else tread depths
  std::vector<std::pair<double, double>> checkpoints;  ///< (time [s], mass [kg] or depth x mass per depth [kg])
  std::vector<std::pair<double, int>> cycles;      ///< (time, id)
  std::vector<std::pair<double, double>> forces;   ///< (time, Fy [N])
};

constexpr const char* kInputNames[kInputKindCount] = {"load", "slip", "speed", "tread_temperature"};
/// Bag-wide recorded covariates (std_msgs/String "name=value"), in effect from their stamp on.
constexpr const char* kCovariateTopic = "measured/covariate";

/// The covariate messages as (time, name, value), in time order; the names in first-seen order.
std::vector<std::tuple<double, std::string, std::string>> readCovariates(rosbag::Bag& bag, const std::string& path,
                                                                         const std::string& topic,
                                                                         std::vector<std::string>* names) {
  std::vector<std::tuple<double, std::string, std::string>> out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic))) {
    auto msg = m.instantiate<std_msgs::String>();
    if (!msg) throw std::runtime_error(path + ": " + topic + " is not std_msgs/String");
    const std::size_t eq = msg->data.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == msg->data.size())
      throw std::runtime_error(path + ": " + topic + " at t = " + std::to_string(m.getTime().toSec()) + ": '" +
                               msg->data + "' is not name=value");
    const std::string name = msg->data.substr(0, eq);
    if (name == "wheel") throw std::runtime_error(path + ": " + topic + ": 'wheel' is the reader's own covariate");
    if (std::find(names->begin(), names->end(), name) == names->end()) names->push_back(name);
    out.emplace_back(m.getTime().toSec(), name, msg->data.substr(eq + 1));
  }
  return out;
}

/// Feeds the wheels' samples to their segmenters on worker threads while the calling thread reads the bag (decoding
/// the messages and binning the points each take about half of the time). There is one reader, so each segmenter
/// gets its wheel's samples in the bag's order and the segments do not depend on the threads.
class SegmenterPipeline {
 public:
  /// workers < 1: the samples go to the segmenters on the calling thread.
  SegmenterPipeline(std::vector<std::unique_ptr<DriveSegmenter>>* segmenters, int workers)
      : segmenters_(*segmenters),
        pending_(segmenters->size()),
        workers_(static_cast<std::size_t>(std::max(0, workers))) {
    for (Worker& w : workers_) w.thread = std::thread([this, &w] { run(&w); });
  }
  ~SegmenterPipeline() { stop(); }

  /// @throw std::runtime_error once a segmenter has failed (finish() then rethrows its error).
  void add(std::size_t wheel, const InputSample& sample) {
    if (workers_.empty()) return segmenters_[wheel]->addSample(sample);
    if (failed_) throw std::runtime_error("a segmenter failed");
    std::vector<InputSample>& batch = pending_[wheel];
    batch.push_back(sample);
    if (batch.size() >= kBatch) hand(wheel);
  }
  /// Hands over what is left and waits for the workers; rethrows the first error of a segmenter.
  void finish() {
    for (std::size_t wheel = 0; wheel < pending_.size() && !workers_.empty() && !failed_; ++wheel)
      if (!pending_[wheel].empty()) hand(wheel);
    stop();
    if (error_) std::rethrow_exception(error_);
  }

 private:
  static constexpr std::size_t kBatch = 4096;  ///< samples handed over at a time
  static constexpr std::size_t kQueued = 64;   ///< batches a worker may have waiting before the reader waits
  struct Batch {
    std::size_t wheel;
    std::vector<InputSample> samples;
  };
  struct Worker {
    std::mutex lock;
    std::condition_variable changed;
    std::deque<Batch> queue;
    bool closed = false;
    std::thread thread;
  };

  void hand(std::size_t wheel) {
    Worker& w = workers_[wheel % workers_.size()];  // a wheel always goes to one worker: its batches stay in order
    std::unique_lock<std::mutex> guard(w.lock);
    w.changed.wait(guard, [&] { return w.queue.size() < kQueued || failed_; });
    if (failed_) return;  // add() and finish() report the segmenter's error
    w.queue.push_back({wheel, std::move(pending_[wheel])});
    pending_[wheel].clear();
    w.changed.notify_all();
  }
  void run(Worker* w) {
    for (;;) {
      Batch batch;
      {
        std::unique_lock<std::mutex> guard(w->lock);
        w->changed.wait(guard, [&] { return !w->queue.empty() || w->closed; });
        if (w->queue.empty()) return;
        batch = std::move(w->queue.front());
        w->queue.pop_front();
        w->changed.notify_all();
      }
      if (failed_) continue;
      try {
        for (const InputSample& s : batch.samples) segmenters_[batch.wheel]->addSample(s);
      } catch (...) {
        const std::lock_guard<std::mutex> guard(error_lock_);
        if (!error_) error_ = std::current_exception();
        failed_ = true;
        for (Worker& other : workers_) {
          const std::lock_guard<std::mutex> wake(other.lock);
          other.changed.notify_all();
        }
      }
    }
  }
  void stop() {
    for (Worker& w : workers_) {
      {
        const std::lock_guard<std::mutex> guard(w.lock);
        w.closed = true;
      }
      w.changed.notify_all();
    }
    for (Worker& w : workers_)
      if (w.thread.joinable()) w.thread.join();
  }

  std::vector<std::unique_ptr<DriveSegmenter>>& segmenters_;
  std::vector<std::vector<InputSample>> pending_;  ///< per wheel, not yet handed over
  std::deque<Worker> workers_;
  std::atomic<bool> failed_{false};
  std::mutex error_lock_;
  std::exception_ptr error_;
};

/// Topic (without a leading slash) -> the bag's spelling.
using BagTopics = std::map<std::string, std::string>;
/// Recorded covariates as (time, name, value), in time order (readCovariates).
using RecordedCovariates = std::vector<std::tuple<double, std::string, std::string>>;

/// The wheels with checkpoint topics (wheels/<w>/measured/mass or tread_depth), by name.
std::map<std::string, WheelRecord> measuredWheels(const std::string& path, const BagTopics& topics) {
  std::map<std::string, WheelRecord> wheels;
  for (const auto& [topic, spelled] : topics) {
    if (topic.rfind("wheels/", 0) != 0) continue;
    for (const std::string suffix : {"/measured/mass", "/measured/tread_depth"}) {
      if (topic.size() > suffix.size() + 7 && topic.compare(topic.size() - suffix.size(), suffix.size(), suffix) == 0) {
        const std::string name = topic.substr(7, topic.size() - suffix.size() - 7);
        wheels[name].name = name;
        wheels[name].by_mass = wheels[name].by_mass || suffix == "/measured/mass";
      }
    }
  }
  if (wheels.empty())
    throw std::runtime_error(path + ": no topic wheels/<name>/measured/mass or wheels/<name>/measured/tread_depth "
                                    "(std_msgs/Float64 checkpoints)");
  return wheels;
}

/// Pass 1: every wheel's checkpoints (masses, or depths times mass_per_depth), cycles and side forces.
void readMeasurements(rosbag::Bag& bag, const BagTopics& topics, double mass_per_depth,
                      std::map<std::string, WheelRecord>* wheels) {
  std::map<std::string, std::pair<WheelRecord*, int>> measured;  // bag topic -> (wheel, 0 checkpoint 1 cycle 2 Fy)
  for (auto& [name, w] : *wheels) {
    const std::string prefix = "wheels/" + name + "/measured/";
    const std::string checkpoint = prefix + (w.by_mass ? "mass" : "tread_depth");
    measured[topics.at(checkpoint)] = {&w, 0};
    if (topics.count(prefix + "cycle")) measured[topics.at(prefix + "cycle")] = {&w, 1};
    if (topics.count(prefix + "side_force")) measured[topics.at(prefix + "side_force")] = {&w, 2};
  }
  std::vector<std::string> measured_topics;
  for (const auto& m : measured) measured_topics.push_back(m.first);
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(measured_topics))) {
    auto& [w, what] = measured.at(m.getTopic());
    const double t = m.getTime().toSec();
    if (what == 0) {
      auto msg = m.instantiate<std_msgs::Float64>();
      if (!msg) throw std::runtime_error(m.getTopic() + " is not std_msgs/Float64");
      w->checkpoints.emplace_back(t, w->by_mass ? msg->data : msg->data * mass_per_depth);
    } else if (what == 1) {
      if (auto msg = m.instantiate<std_msgs::Int32>()) w->cycles.emplace_back(t, msg->data);
    } else if (auto msg = m.instantiate<geometry_msgs::WrenchStamped>()) {
      w->forces.emplace_back(t, msg->wrench.force.y);
    }
  }
}

/// Pass 2: every wheel's inputs through its segmenter, on one grid that starts at the first input of any wheel; the
/// segments of each wheel of `order`.
std::vector<std::vector<DriveSegment>> wheelSegments(rosbag::Bag& bag, const std::string& path,
                                                     const BagTopics& topics, const ReplaySettings& replay,
                                                     const std::vector<WheelRecord*>& order) {
  std::map<std::string, std::pair<int, InputKind>> inputs;  // bag topic -> (wheel index, kind)
  for (std::size_t wi = 0; wi < order.size(); ++wi) {
    const WheelRecord& w = *order[wi];
    if (w.checkpoints.size() < 2)
      throw std::runtime_error(path + ": fewer than two " + (w.by_mass ? "mass" : "tread depth") +
                               " checkpoints on wheels/" + w.name + "/measured/: no segment to compare");
    for (int k = 0; k < kInputKindCount; ++k) {
      const std::string topic = "wheels/" + w.name + "/" + kInputNames[k];
      if (topics.count(topic)) {
        inputs[topics.at(topic)] = {static_cast<int>(wi), static_cast<InputKind>(k)};
      } else if (static_cast<InputKind>(k) != InputKind::kTemperature) {
        throw std::runtime_error(path + ": missing input topic " + topic + " of wheel " + w.name);
      }
    }
  }
  std::vector<std::string> input_topics;
  for (const auto& i : inputs) input_topics.push_back(i.first);
  const double start_s = rosbag::View(bag, rosbag::TopicQuery(input_topics)).getBeginTime().toSec();
  std::vector<std::unique_ptr<DriveSegmenter>> segmenters;
  for (WheelRecord* w : order) {
    std::vector<double> times;
    for (const auto& c : w->checkpoints) times.push_back(c.first);
    try {
      segmenters.push_back(std::make_unique<DriveSegmenter>(replay, PointCellParams(), times, start_s));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(path + ": wheel " + w->name + ": " + e.what());
    }
  }
  SegmenterPipeline pipeline(&segmenters, std::min(defaultJobs(), static_cast<int>(order.size()) + 1) - 1);
  try {
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(input_topics))) {
      const auto& [wheel, kind] = inputs.at(m.getTopic());
      pipeline.add(static_cast<std::size_t>(wheel), inputSample(m, kind));
    }
  } catch (...) {
    pipeline.finish();  // a segmenter's error first: the reader stopped because of it
    throw;
  }
  pipeline.finish();
  std::vector<std::vector<DriveSegment>> segments;
  for (auto& segmenter : segmenters) segments.push_back(segmenter->finish());
  return segments;
}

/// The run record of segment j of wheel w. @throw std::runtime_error for a segment without motion or whose mass (or
/// depth) did not decrease.
RunRecord segmentRecord(const std::string& path, const WheelRecord& w, std::size_t j, const DriveSegment& seg,
                        const std::vector<std::string>& covariate_names, const RecordedCovariates& covariates,
                        const ReplaySettings& replay) {
  const std::string where = path + ": wheel " + w.name + ", segment " + std::to_string(j + 1) +
                            " (ending at t = " + std::to_string(seg.end_s) + " s)";
  if (!(seg.integrated_s > 0.0) || !(seg.distance_m > 0.0))
    throw std::runtime_error(where + ": no motion with all of load, slip and speed known (inputs older than " +
                             std::to_string(replay.estimator.stale_timeout_s) + " s are not integrated)");
  const double loss = w.checkpoints[j].second - w.checkpoints[j + 1].second;
  if (!(loss > 0.0))
    throw std::runtime_error(where + (w.by_mass ? ": the mass did not decrease (" : ": the tread depth did not "
                                                                                   "decrease (mass equivalent ") +
                             std::to_string(loss) + " kg)");
  RunRecord r = driveSegmentRecord(seg);
  // Side-force samples in [start, end): one stamped at a checkpoint belongs to the segment that starts there.
  double fy_sum = 0.0;
  int fy_n = 0;
  for (const auto& [tf, fy] : w.forces)
    if (tf >= seg.start_s && tf < seg.end_s) {
      fy_sum += fy;
      ++fy_n;
    }
  r.measured_side_force_n = fy_n > 0 ? fy_sum / fy_n : NAN;
  r.measured_wear_rate_kg_per_m = loss / seg.distance_m;
  r.condition_id = w.name + "/segment_" + std::to_string(j + 1);
  // The cycle in effect before the checkpoint: a cycle message stamped at the checkpoint itself starts the next
  // segment (messages of equal time have no defined order in a bag).
  r.cycle_id = -1;
  for (const auto& [tc, id] : w.cycles)
    if (tc < seg.end_s) r.cycle_id = id;
  r.run_order = static_cast<int>(j + 1);
  r.covariates = {seg.distance_m, seg.end_s - seg.start_s, loss};
  r.text_covariates = {w.name};
  // Each recorded covariate as in effect before the segment's end (as the cycle), "unknown" before its first.
  for (const std::string& name : covariate_names) {
    std::string value = "unknown";
    for (const auto& [tc, n, v] : covariates)
      if (n == name && tc < seg.end_s) value = v;
    r.text_covariates.push_back(value);
  }
  std::string error;
  if (!r.op.validate(&error)) throw std::runtime_error(where + ": " + error);
  return r;
}

}  // namespace

RunTable readDiagnosisBag(const std::string& path, const TireParams& tire, const ReplaySettings& replay) {
  std::string error;
  if (!tire.validate(&error)) throw std::runtime_error("tire parameters: " + error);
  checkBagRecords(path);
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": cannot open the bag: " + e.what());
  }
  RunTable table;
  table.covariate_names = {"distance_m", "duration_s", "mass_loss_kg"};
  table.text_covariate_names = {"wheel"};
  try {
    BagTopics topics;
    for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections())
      topics[withoutLeadingSlash(c->topic)] = c->topic;
    std::map<std::string, WheelRecord> wheels = measuredWheels(path, topics);
    std::vector<std::string> covariate_names;
    const RecordedCovariates covariates = topics.count(kCovariateTopic)
                                              ? readCovariates(bag, path, topics.at(kCovariateTopic), &covariate_names)
                                              : RecordedCovariates{};
    for (const std::string& name : covariate_names) table.text_covariate_names.push_back(name);
    readMeasurements(bag, topics, tire.material.massPerDepth_kg_per_m(), &wheels);
    std::vector<WheelRecord*> order;
    for (auto& [name, w] : wheels) order.push_back(&w);
    const std::vector<std::vector<DriveSegment>> segments = wheelSegments(bag, path, topics, replay, order);
    for (std::size_t wi = 0; wi < order.size(); ++wi)
      for (std::size_t j = 0; j < segments[wi].size(); ++j)
        table.runs.push_back(
            segmentRecord(path, *order[wi], j, segments[wi][j], covariate_names, covariates, replay));
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(path + ": " + e.what());
  } catch (const ros::Exception& e) {
    throw std::runtime_error(path + ": a message could not be decoded: " + e.what());
  }
  return table;
}

}  // namespace diagnosis
}  // namespace tread_wear
