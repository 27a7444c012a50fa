#include "tread_wear/ros/bag/diagnosis_bag.h"

#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include <geometry_msgs/WrenchStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int32.h>

#include "tread_wear/ros/bag/bag_check.h"
#include <tread_wear/TreadTemperature.h>
#include <tread_wear/WheelLoad.h>
#include <tread_wear/WheelSlip.h>
#include <tread_wear/WheelSpeed.h>

namespace tread_wear {
namespace diagnosis {
namespace {

/// Time-weighted sums of one segment (inputs held at their last value between messages).
struct Segment {
  double t = 0.0, moving_t = 0.0, distance = 0.0;
  double speed = 0.0, alpha = 0.0, kappa = 0.0, curvature = 0.0, load = 0.0, load2 = 0.0;
  double temp = 0.0, temp_t = 0.0;
};

}  // namespace

RunTable readDiagnosisBag(const std::string& path) {
  checkBagRecords(path);
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": cannot open the bag: " + e.what());
  }
  std::set<std::string> wheels;
  {
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      const std::string& t = c->topic;
      const std::string suffix = "/measured/mass";
      if (t.size() > suffix.size() && t.compare(t.size() - suffix.size(), suffix.size(), suffix) == 0) {
        std::string w = t.substr(0, t.size() - suffix.size());
        if (!w.empty() && w[0] == '/') w.erase(0, 1);
        if (w.rfind("wheels/", 0) == 0) wheels.insert(w.substr(7));
      }
    }
  }
  if (wheels.empty())
    throw std::runtime_error(path + ": no topic wheels/<name>/measured/mass (std_msgs/Float64 mass checkpoints)");
  const std::string prefix = "wheels/" + *wheels.begin() + "/";
  auto topic = [&](const char* name) { return prefix + name; };
  std::vector<std::string> topics;  // with and without the leading slash
  for (const char* name : {"load", "slip", "speed", "tread_temperature", "measured/side_force", "measured/mass",
                           "measured/cycle"}) {
    topics.push_back(topic(name));
    topics.push_back("/" + topic(name));
  }
  auto ends = [](const std::string& t, const std::string& s) {
    return t.size() >= s.size() && t.compare(t.size() - s.size(), s.size(), s) == 0;
  };
  RunTable table;
  table.covariate_names = {"distance_m", "duration_s", "mass_loss_kg"};
  double speed = NAN, alpha = NAN, kappa = 0.0, curvature = 0.0, load = NAN, temp = NAN;
  std::vector<std::pair<double, int>> cycles;     // (time, id) of every cycle message
  std::vector<std::pair<double, double>> forces;  // (time, Fy) of the side-force samples not yet assigned
  bool have_mass = false;
  double mass = 0.0, last_t = NAN;
  Segment seg;
  int segment_index = 0;
  try {
    rosbag::View view(bag, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& m : view) {
      const double t = m.getTime().toSec();
      // Integrate the held inputs over [last_t, t).
      if (have_mass && std::isfinite(last_t) && std::isfinite(speed) && std::isfinite(alpha) && std::isfinite(load)) {
        const double dt = t - last_t;
        if (dt > 0.0) {
          seg.t += dt;
          seg.distance += speed * dt;
          seg.speed += speed * dt;
          seg.alpha += alpha * dt;
          seg.kappa += kappa * dt;
          seg.curvature += curvature * dt;
          seg.load += load * dt;
          seg.load2 += load * load * dt;
          if (std::isfinite(temp)) {
            seg.temp += temp * dt;
            seg.temp_t += dt;
          }
        }
      }
      last_t = t;
      const std::string& tp = m.getTopic();
      if (ends(tp, "/load")) {
        if (auto msg = m.instantiate<tread_wear::WheelLoad>()) load = msg->load_n;
      } else if (ends(tp, "/slip")) {
        if (auto msg = m.instantiate<tread_wear::WheelSlip>()) {
          alpha = msg->slip_angle_rad;
          kappa = msg->slip_ratio;
          curvature = msg->path_curvature_per_m;
        }
      } else if (ends(tp, "/speed")) {
        if (auto msg = m.instantiate<tread_wear::WheelSpeed>()) speed = msg->speed_mps;
      } else if (ends(tp, "/tread_temperature")) {
        if (auto msg = m.instantiate<tread_wear::TreadTemperature>()) temp = msg->temperature_c;
      } else if (ends(tp, "/measured/side_force")) {
        if (auto msg = m.instantiate<geometry_msgs::WrenchStamped>()) forces.emplace_back(t, msg->wrench.force.y);
      } else if (ends(tp, "/measured/cycle")) {
        if (auto msg = m.instantiate<std_msgs::Int32>()) cycles.emplace_back(t, msg->data);
      } else if (ends(tp, "/measured/mass")) {
        auto msg = m.instantiate<std_msgs::Float64>();
        if (!msg) throw std::runtime_error(tp + " is not std_msgs/Float64");
        if (have_mass) {
          ++segment_index;
          const std::string where = path + ": segment " + std::to_string(segment_index) + " (ending at t = " +
                                    std::to_string(t) + " s)";
          if (!(seg.t > 0.0) || !(seg.distance > 0.0))
            throw std::runtime_error(where + ": no motion with all of load, slip and speed known");
          const double loss = mass - msg->data;
          if (!(loss > 0.0))
            throw std::runtime_error(where + ": the mass did not decrease (" + std::to_string(loss) + " kg)");
          RunRecord r;
          r.op.speed_mps = seg.speed / seg.t;
          r.op.slip_angle_rad = seg.alpha / seg.t;
          r.op.slip_ratio = seg.kappa / seg.t;
          r.op.path_curvature_per_m = seg.curvature / seg.t;
          r.op.load_n = seg.load / seg.t;
          r.op.tread_temperature_c = seg.temp_t > 0.5 * seg.t ? seg.temp / seg.temp_t : NAN;
          r.load_std_n = std::sqrt(std::max(0.0, seg.load2 / seg.t - r.op.load_n * r.op.load_n));
          // Side-force samples in [previous checkpoint, this checkpoint): one stamped at a checkpoint belongs to the
          // segment that starts there.
          double fy_sum = 0.0;
          int fy_n = 0;
          std::vector<std::pair<double, double>> later;
          for (const auto& [tf, fy] : forces) {
            if (tf < t) {
              fy_sum += fy;
              ++fy_n;
            } else {
              later.emplace_back(tf, fy);
            }
          }
          forces.swap(later);
          r.measured_side_force_n = fy_n > 0 ? fy_sum / fy_n : NAN;
          r.measured_wear_rate_kg_per_m = loss / seg.distance;
          r.condition_id = "segment_" + std::to_string(segment_index);
          // The cycle in effect before the checkpoint: a cycle message stamped at the checkpoint itself starts the
          // next segment (messages of equal time have no defined order in a bag).
          r.cycle_id = -1;
          for (const auto& [tc, id] : cycles)
            if (tc < t) r.cycle_id = id;
          r.run_order = segment_index;
          r.covariates = {seg.distance, seg.t, loss};
          std::string error;
          if (!r.op.validate(&error)) throw std::runtime_error(where + ": " + error);
          table.runs.push_back(r);
        }
        if (!have_mass) forces.clear();  // samples before the first checkpoint belong to no segment
        have_mass = true;
        mass = msg->data;
        seg = Segment{};
      }
    }
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  if (table.runs.empty())
    throw std::runtime_error(path + ": fewer than two mass checkpoints on " + topic("measured/mass") +
                             ": no segment to compare");
  return table;
}

}  // namespace diagnosis
}  // namespace tread_wear
