#include "tread_wear/ros/bag/drive_bag_reader.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>

#include <map>

#include "tread_wear/TreadTemperature.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/ros/bag/drive_bag_writer.h"

namespace tread_wear {

namespace {

/// Checks that a topic exists in the bag with the expected type; returns false if absent.
template <typename M>
bool checkTopic(const std::string& path, const std::map<std::string, const rosbag::ConnectionInfo*>& connections,
                const std::string& topic, bool required) {
  const auto it = connections.find(topic);
  if (it == connections.end()) {
    if (required) throw BagError(path + ": missing topic " + topic + " (" + ros::message_traits::datatype<M>() + ")");
    return false;
  }
  const std::string expected = ros::message_traits::datatype<M>();
  if (it->second->datatype != expected)
    throw BagError(path + ": topic " + topic + " has type " + it->second->datatype + ", expected " + expected);
  if (it->second->md5sum != ros::message_traits::md5sum<M>())
    throw BagError(path + ": topic " + topic + " has a different definition of " + expected + " (md5 " +
                   it->second->md5sum + ", expected " + ros::message_traits::md5sum<M>() + ")");
  return true;
}

}  // namespace

InputSample inputSample(const rosbag::MessageInstance& m, InputKind kind) {
  InputSample sample;
  sample.t_s = m.getTime().toSec();
  sample.kind = kind;
  switch (kind) {
    case InputKind::kLoad: sample.value[0] = m.instantiate<WheelLoad>()->load_n; break;
    case InputKind::kSlip: {
      const auto s = m.instantiate<WheelSlip>();
      sample.value[0] = s->slip_angle_rad;
      sample.value[1] = s->slip_ratio;
      sample.value[2] = s->path_curvature_per_m;
      break;
    }
    case InputKind::kSpeed: sample.value[0] = m.instantiate<WheelSpeed>()->speed_mps; break;
    case InputKind::kTemperature: sample.value[0] = m.instantiate<TreadTemperature>()->temperature_c; break;
  }
  return sample;
}

DriveInfo readDriveBag(const std::string& path, const ReplayConfig& config, DriveReplay* replay) {
  checkBagRecords(path);  // also the error for a missing or unreadable file
  DriveInfo info;
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": not a readable bag (corrupt, truncated or unindexed: try `rosbag reindex`): " + e.what());
  }
  try {
    std::map<std::string, const rosbag::ConnectionInfo*> connections;
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) connections[c->topic] = c;

    // Which topic feeds which wheel and input.
    struct Route {
      int wheel;
      InputKind kind;
    };
    std::map<std::string, Route> routes;
    for (int w = 0; w < static_cast<int>(config.wheels.size()); ++w) {
      const std::size_t i = static_cast<std::size_t>(w);
      checkTopic<WheelLoad>(path, connections, config.load_topics[i], true);
      checkTopic<WheelSlip>(path, connections, config.slip_topics[i], true);
      checkTopic<WheelSpeed>(path, connections, config.speed_topics[i], true);
      routes[config.load_topics[i]] = {w, InputKind::kLoad};
      routes[config.slip_topics[i]] = {w, InputKind::kSlip};
      routes[config.speed_topics[i]] = {w, InputKind::kSpeed};
      if (checkTopic<TreadTemperature>(path, connections, config.temperature_topics[i], false))
        routes[config.temperature_topics[i]] = {w, InputKind::kTemperature};
    }
    if (connections.count(kDriveInfoTopic) != 0) {
      checkTopic<std_msgs::String>(path, connections, kDriveInfoTopic, false);
      rosbag::View view(bag, rosbag::TopicQuery(std::string(kDriveInfoTopic)));
      for (const rosbag::MessageInstance& m : view) {
        const auto text = m.instantiate<std_msgs::String>();
        if (!text) continue;
        try {
          info = {parseDriveInfo(text->data), true};
        } catch (const DriveInfoError& e) {
          throw BagError(path + ": " + kDriveInfoTopic + " is not valid drive metadata: " + e.what());
        }
      }
    }

    std::vector<std::string> topics;
    for (const auto& r : routes) topics.push_back(r.first);
    rosbag::View view(bag, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& m : view) {
      const Route& r = routes.at(m.getTopic());
      replay->addSample(r.wheel, inputSample(m, r.kind));
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": bag data unreadable (corrupt or truncated): " + e.what());
  } catch (const ros::Exception& e) {
    throw BagError(path + ": a message could not be decoded: " + e.what());
  }
  return info;
}

}  // namespace tread_wear
