#include "tread_wear/ros/bag/drive_bag_reader.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

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

/// Reads messages of one type into one reused message object through one reused buffer: no allocation per message
/// once the buffer and the header's frame_id have grown to the largest message.
class MessageDecoder {
 public:
  template <typename M>
  const M& decode(const rosbag::MessageInstance& m, M* msg) {
    if (buffer_.empty()) buffer_.resize(kInitialBytes);
    std::size_t bytes = 0;
    try {
      ros::serialization::OStream out(buffer_.data(), static_cast<std::uint32_t>(buffer_.size()));
      m.write(out);
      bytes = static_cast<std::size_t>(out.getData() - buffer_.data());
    } catch (const ros::serialization::StreamOverrunException&) {  // a larger message: grow once, read again
      buffer_.resize(m.size());
      ros::serialization::OStream out(buffer_.data(), static_cast<std::uint32_t>(buffer_.size()));
      m.write(out);
      bytes = buffer_.size();
    }
    ros::serialization::IStream in(buffer_.data(), static_cast<std::uint32_t>(bytes));
    ros::serialization::deserialize(in, *msg);
    return *msg;
  }

 private:
  static constexpr std::size_t kInitialBytes = 256;
  std::vector<std::uint8_t> buffer_;
};

/// The samples of one input topic in time order, as inputSample() makes them, without allocating per message.
void readTopic(const rosbag::Bag& bag, const std::string& topic, InputKind kind, MessageDecoder* decoder,
               std::vector<InputSample>* samples) {
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  samples->reserve(samples->size() + view.size());
  WheelLoad load;
  WheelSlip slip;
  WheelSpeed speed;
  TreadTemperature temperature;
  for (const rosbag::MessageInstance& m : view) {
    InputSample sample;
    sample.t_s = m.getTime().toSec();
    sample.kind = kind;
    switch (kind) {
      case InputKind::kLoad: sample.value[0] = decoder->decode(m, &load).load_n; break;
      case InputKind::kSlip:
        decoder->decode(m, &slip);
        sample.value[0] = slip.slip_angle_rad;
        sample.value[1] = slip.slip_ratio;
        sample.value[2] = slip.path_curvature_per_m;
        break;
      case InputKind::kSpeed: sample.value[0] = decoder->decode(m, &speed).speed_mps; break;
      case InputKind::kTemperature: sample.value[0] = decoder->decode(m, &temperature).temperature_c; break;
    }
    samples->push_back(sample);
  }
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

    // Which topics feed each wheel, of which input.
    std::vector<std::vector<std::pair<std::string, InputKind>>> wheel_topics(config.wheels.size());
    for (std::size_t i = 0; i < config.wheels.size(); ++i) {
      checkTopic<WheelLoad>(path, connections, config.load_topics[i], true);
      checkTopic<WheelSlip>(path, connections, config.slip_topics[i], true);
      checkTopic<WheelSpeed>(path, connections, config.speed_topics[i], true);
      wheel_topics[i] = {{config.load_topics[i], InputKind::kLoad},
                         {config.slip_topics[i], InputKind::kSlip},
                         {config.speed_topics[i], InputKind::kSpeed}};
      if (checkTopic<TreadTemperature>(path, connections, config.temperature_topics[i], false))
        wheel_topics[i].emplace_back(config.temperature_topics[i], InputKind::kTemperature);
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

    // Topic by topic (a view of one topic needs no merging), each wheel's topics then merged by time: samples of
    // one time stamp are all applied before the same step, so their order among the topics changes nothing.
    MessageDecoder decoder;
    std::vector<InputSample> samples;
    for (std::size_t i = 0; i < wheel_topics.size(); ++i) {
      samples.clear();
      for (const auto& [topic, kind] : wheel_topics[i]) {
        const auto middle = static_cast<std::ptrdiff_t>(samples.size());
        readTopic(bag, topic, kind, &decoder, &samples);
        std::inplace_merge(samples.begin(), samples.begin() + middle, samples.end(),
                           [](const InputSample& a, const InputSample& b) { return a.t_s < b.t_s; });
      }
      for (const InputSample& sample : samples) replay->addSample(static_cast<int>(i), sample);
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": bag data unreadable (corrupt or truncated): " + e.what());
  } catch (const ros::Exception& e) {
    throw BagError(path + ": a message could not be decoded: " + e.what());
  }
  return info;
}

}  // namespace tread_wear
