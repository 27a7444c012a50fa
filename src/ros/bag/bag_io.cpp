#include "tread_wear/ros/bag/bag_io.h"

#include <bzlib.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <roslz4/lz4s.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string_view>

#include "tread_wear/TreadTemperature.h"
#include "tread_wear/VehicleWear.h"
#include "tread_wear/WheelLoad.h"
#include "tread_wear/WheelSlip.h"
#include "tread_wear/WheelSpeed.h"
#include "tread_wear/WheelWear.h"

namespace tread_wear {

namespace {

// rosbag 2.0 records: uint32 header length, header fields (each uint32 length + "name=value"), uint32 data
// length, data; all integers little-endian. The "op" field tells the record type.
constexpr char kOpMessageDefinition = 0x01, kOpMessageData = 0x02, kOpIndexData = 0x04, kOpChunk = 0x05,
               kOpConnection = 0x07;
constexpr std::size_t kVersionLineBytes = 13;  // "#ROSBAG V2.0\n"

std::uint64_t littleEndian(const char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}

/// A record found in `bytes[0, size)` at `pos`: the header fields this check needs, and where its data lie.
struct Record {
  char op = 0;
  std::string_view compression, size;  ///< chunk header fields (views into the bytes)
  std::uint64_t data_pos = 0, data_len = 0, end = 0;
};

/// Parses the record at `pos` of a stretch of `size` bytes whose first `available` are in `bytes` (at least its
/// header and data length, or to the end); an empty string, or what runs past the end or is malformed.
std::string parseRecord(const char* bytes, std::uint64_t available, std::uint64_t size, std::uint64_t pos,
                        Record* r) {
  if (available - pos < 4) return "record header length past the end";
  const std::uint64_t header_len = littleEndian(bytes + pos, 4);
  if (header_len > available - pos - 4) return "record header of " + std::to_string(header_len) + " bytes past the end";
  std::uint64_t at = pos + 4;
  const std::uint64_t header_end = at + header_len;
  *r = Record();
  while (at < header_end) {
    if (header_end - at < 4) return "header field length past the header";
    const std::uint64_t field_len = littleEndian(bytes + at, 4);
    at += 4;
    if (field_len > header_end - at) return "header field of " + std::to_string(field_len) + " bytes past the header";
    const std::string_view field(bytes + at, field_len);
    const auto eq = field.find('=');
    if (eq == std::string_view::npos) return "header field without '='";
    const std::string_view name = field.substr(0, eq), value = field.substr(eq + 1);
    if (name == "op" && value.size() == 1) r->op = value[0];
    if (name == "compression") r->compression = value;
    if (name == "size") r->size = value;
    at += field_len;
  }
  if (available - header_end < 4) return "record data length past the end";
  r->data_len = littleEndian(bytes + header_end, 4);
  r->data_pos = header_end + 4;
  if (r->data_len > size - r->data_pos) return "record data of " + std::to_string(r->data_len) + " bytes past the end";
  r->end = r->data_pos + r->data_len;
  return "";
}

/// Largest decompressed chunk the check accepts [bytes]. rosbag allocates a compressed chunk's size field before it
/// decompresses, so a corrupt one must not ask for gigabytes (rosbag's chunks hold about 768 KB by default; a chunk
/// exceeds that only by its last message). An uncompressed chunk's size is its data length, within the file.
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;

/// Decompresses a bz2 or lz4 chunk (the codecs rosbag writes) into `out`, sized to the chunk's size field; false
/// when the data do not decompress to exactly that many bytes.
bool decompressChunk(std::string_view compression, std::vector<char>* in, std::vector<char>* out) {
  unsigned int out_len = static_cast<unsigned int>(out->size());
  const unsigned int in_len = static_cast<unsigned int>(in->size());
  const bool ok = compression == "bz2"
                      ? BZ2_bzBuffToBuffDecompress(out->data(), &out_len, in->data(), in_len, 0, 0) == BZ_OK
                      : roslz4_buffToBuffDecompress(in->data(), in_len, out->data(), &out_len) == ROSLZ4_OK;
  return ok && out_len == out->size();
}

nlohmann::json vehicleJson(const VehicleParams& p) {
  return {{"name", p.name},
          {"mass_kg", p.mass_kg},
          {"wheelbase_m", p.wheelbase_m},
          {"cog_to_front_axle_m", p.cog_to_front_axle_m},
          {"cog_height_m", p.cog_height_m},
          {"track_front_m", p.track_front_m},
          {"track_rear_m", p.track_rear_m},
          {"front_roll_stiffness_share", p.front_roll_stiffness_share},
          {"drive_layout", driveLayoutName(p.drive_layout)},
          {"all_wheel_front_drive_share", p.all_wheel_front_drive_share},
          {"brake_balance_front", p.brake_balance_front},
          {"drag_coefficient", p.drag_coefficient},
          {"frontal_area_m2", p.frontal_area_m2},
          {"air_density_kg_per_m3", p.air_density_kg_per_m3},
          {"rolling_resistance_coefficient", p.rolling_resistance_coefficient},
          {"cornering_stiffness_front_per_rad", p.cornering_stiffness_front_per_rad},
          {"cornering_stiffness_rear_per_rad", p.cornering_stiffness_rear_per_rad},
          {"longitudinal_slip_stiffness", p.longitudinal_slip_stiffness},
          {"gravity_mps2", p.gravity_mps2}};
}

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

DriveStats writeDriveBag(const std::string& path, const SpeedProfile& profile, const Route& route,
                         const VehicleModel& vehicle, const RouteParams& route_params, const DriveOptions& options) {
  if (!(options.rate_hz > 0.0) || options.wheel_names.size() != static_cast<std::size_t>(kWheelCount))
    throw BagError(path + ": drive needs rate_hz > 0 and 4 wheel names");
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": cannot write the bag: " + e.what());
  }
  std::vector<std::string> load_topics, slip_topics, speed_topics, frames;
  for (const std::string& name : options.wheel_names) {
    load_topics.push_back("/wheels/" + name + "/load");
    slip_topics.push_back("/wheels/" + name + "/slip");
    speed_topics.push_back("/wheels/" + name + "/speed");
    frames.push_back("wheel_" + name);
  }
  DriveStats stats;
  const std::size_t n = static_cast<std::size_t>(std::floor(profile.duration_s() * options.rate_hz + 1e-9)) + 1;
  WheelLoad load;
  WheelSlip slip;
  WheelSpeed speed;
  VehicleState state;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = profile.startTime_s() + static_cast<double>(k) / options.rate_hz;
    const VehicleMotion motion{profile.speed(t), profile.acceleration(t), route.curvature(profile.distance(t))};
    vehicle.evaluate(motion, &state);
    stats.max_abs_lateral_accel_mps2 = std::max(stats.max_abs_lateral_accel_mps2, std::fabs(state.lateral_accel_mps2));
    const ros::Time stamp(t - profile.startTime_s() + kDriveTimeOffset_s);
    for (int i = 0; i < kWheelCount; ++i) {
      const WheelState& w = state.wheels[static_cast<std::size_t>(i)];
      load.header.stamp = slip.header.stamp = speed.header.stamp = stamp;
      load.header.frame_id = slip.header.frame_id = speed.header.frame_id = frames[i];
      load.load_n = w.load_n;
      slip.slip_angle_rad = w.slip_angle_rad;
      slip.slip_ratio = w.slip_ratio;
      slip.path_curvature_per_m = w.path_curvature_per_m;
      speed.speed_mps = w.speed_mps;
      bag.write(load_topics[i], stamp, load);
      bag.write(slip_topics[i], stamp, slip);
      bag.write(speed_topics[i], stamp, speed);
    }
  }
  stats.samples = n;
  stats.duration_s = profile.duration_s();
  stats.distance_m = profile.totalDistance_m();

  nlohmann::json info;
  info["format"] = "tread_wear_drive";
  info["version"] = 1;
  info["profile"] = profile.name();
  info["rate_hz"] = options.rate_hz;
  info["time_offset_s"] = kDriveTimeOffset_s - profile.startTime_s();
  info["duration_s"] = stats.duration_s;
  info["distance_m"] = stats.distance_m;
  info["wheels"] = options.wheel_names;
  nlohmann::json phases = nlohmann::json::array();
  for (const ProfilePhase& p : profile.phases())
    phases.push_back({{"name", p.name}, {"start_s", p.start_s}, {"end_s", p.end_s}});
  info["phases"] = phases;
  info["vehicle"] = vehicleJson(vehicle.params());
  std::map<std::string, int> event_counts;
  for (const RouteEvent& e : route.events()) ++event_counts[routeEventKindName(e.kind)];
  info["route"] = {{"lateral_accel_limit_mps2", route_params.lateral_accel_limit_mps2},
                   {"seed", route_params.seed},
                   {"events", event_counts},
                   {"max_abs_lateral_accel_mps2", stats.max_abs_lateral_accel_mps2}};
  std_msgs::String text;
  text.data = info.dump(2);
  bag.write(kDriveInfoTopic, ros::Time(kDriveTimeOffset_s), text);
  bag.close();
  return stats;
}

void checkBagRecords(const std::string& path) {
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);  // an error for a directory too
  std::ifstream file(path, std::ios::binary);
  // Reads [offset, offset + count) of the file (count <= size - offset) into `out`.
  auto readAt = [&](std::uint64_t offset, std::uint64_t count, std::vector<char>* out) {
    out->resize(count);
    if (!file.seekg(static_cast<std::streamoff>(offset)) || !file.read(out->data(), static_cast<std::streamsize>(count)))
      throw BagError(path + ": cannot read the bag at byte " + std::to_string(offset));
  };
  if (ec || !file) throw BagError(path + ": cannot open the bag (missing or unreadable file)");
  std::vector<char> head, data;  // a record's header, and the data of a chunk or index record
  std::vector<char> unpacked;    // a compressed chunk's data, decompressed
  if (size >= kVersionLineBytes) readAt(0, kVersionLineBytes, &head);
  if (size < kVersionLineBytes || std::string(head.data(), kVersionLineBytes) != "#ROSBAG V2.0\n")
    return;  // not a 2.0 bag: rosbag reads older versions and names what it cannot read
  auto corrupt = [&](const std::string& what, std::uint64_t at) {
    return BagError(path + ": bag data unreadable (corrupt): " + what + " at byte " + std::to_string(at));
  };
  // Record starts of the last checked chunk (relative to its data, decompressed if compressed; ascending) with
  // their ops.
  std::vector<std::pair<std::uint64_t, char>> chunk_records;
  bool chunk_checked = false;
  Record r;
  // One record at a time: its header is read first, then the data of a chunk or index record only, so memory
  // stays at one chunk whatever the size of the bag.
  for (std::uint64_t pos = kVersionLineBytes; pos < size; pos += r.end) {
    readAt(pos, std::min<std::uint64_t>(size - pos, 4), &head);
    if (head.size() == 4)  // then up to the data length: uint32 header length, header, uint32 data length
      readAt(pos, std::min(size - pos, 8 + littleEndian(head.data(), 4)), &head);
    const std::string error = parseRecord(head.data(), head.size(), size - pos, 0, &r);
    if (!error.empty())
      throw BagError(path + ": not a readable bag (corrupt or truncated: " + error + " of the file at byte " +
                     std::to_string(pos) + "; `rosbag reindex` may recover a truncated one)");
    const std::uint64_t data_at = pos + r.data_pos;
    if (r.op == kOpChunk) {
      chunk_records.clear();
      const bool compressed = r.compression == "bz2" || r.compression == "lz4";
      chunk_checked = compressed || r.compression == "none";
      if (!chunk_checked) continue;  // rosbag names a compression it does not know
      // The size field: the data length of an uncompressed chunk, the decompressed length of a compressed one. A
      // missing field equals no uint32 data length and exceeds the cap.
      const std::uint64_t chunk_len =
          r.size.size() == 4 ? littleEndian(r.size.data(), 4) : std::numeric_limits<std::uint64_t>::max();
      if (!compressed && chunk_len != r.data_len)
        throw corrupt("uncompressed chunk whose size field differs from its data length", pos);
      if (compressed && chunk_len > kMaxChunkBytes)
        throw corrupt("chunk whose size field is missing or above " + std::to_string(kMaxChunkBytes) + " bytes", pos);
      readAt(data_at, r.data_len, &data);
      if (compressed) {
        unpacked.resize(chunk_len);
        if (!decompressChunk(r.compression, &data, &unpacked))
          throw corrupt(std::string(r.compression) + " chunk that does not decompress to its size field (" +
                            std::to_string(chunk_len) + " bytes)",
                        pos);
      }
      const std::vector<char>& chunk = compressed ? unpacked : data;
      Record inner;
      for (std::uint64_t at = 0; at < chunk_len; at = inner.end) {
        const std::string inner_error = parseRecord(chunk.data(), chunk_len, chunk_len, at, &inner);
        if (!inner_error.empty() && compressed)
          throw corrupt(inner_error + " of its decompressed chunk (at its byte " + std::to_string(at) + ")", pos);
        if (!inner_error.empty()) throw corrupt(inner_error + " of its chunk", data_at + at);
        chunk_records.emplace_back(at, inner.op);
      }
    } else if (r.op == kOpIndexData && chunk_checked) {
      if (r.data_len % 12 != 0) throw corrupt("index data not a whole number of entries", pos);
      readAt(data_at, r.data_len, &data);
      for (std::uint64_t e = 0; e < r.data_len; e += 12) {
        const std::uint64_t offset = littleEndian(data.data() + e + 8, 4);
        // rosbag reads from the entry's record on, past connection and definition records, to a message.
        auto it = std::lower_bound(chunk_records.begin(), chunk_records.end(), std::make_pair(offset, char{0}));
        if (it != chunk_records.end() && it->first != offset) it = chunk_records.end();
        while (it != chunk_records.end() && (it->second == kOpConnection || it->second == kOpMessageDefinition)) ++it;
        if (it == chunk_records.end() || it->second != kOpMessageData)
          throw corrupt("index entry pointing at no message of its chunk (offset " + std::to_string(offset) + ")",
                        data_at + e);
      }
    }
  }
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
          info.json = nlohmann::json::parse(text->data);
          info.time_offset_s = info.json.value("time_offset_s", 0.0);
          for (const auto& p : info.json.value("phases", nlohmann::json::array()))
            info.phases.push_back(
                {p.at("name").get<std::string>(), p.at("start_s").get<double>(), p.at("end_s").get<double>()});
          info.present = true;
        } catch (const nlohmann::json::exception& e) {
          throw BagError(path + ": " + kDriveInfoTopic + " is not valid drive metadata: " + e.what());
        }
      }
    }

    std::vector<std::string> topics;
    for (const auto& r : routes) topics.push_back(r.first);
    rosbag::View view(bag, rosbag::TopicQuery(topics));
    InputSample sample;
    for (const rosbag::MessageInstance& m : view) {
      const Route& r = routes.at(m.getTopic());
      sample.t_s = m.getTime().toSec();
      sample.kind = r.kind;
      switch (r.kind) {
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
      replay->addSample(r.wheel, sample);
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": bag data unreadable (corrupt or truncated): " + e.what());
  } catch (const ros::Exception& e) {
    throw BagError(path + ": a message could not be decoded: " + e.what());
  }
  return info;
}

void writeWearBag(const std::string& path, const DriveReplay& replay, const ReplayConfig& config,
                  std::uint64_t decimation) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": cannot write the bag: " + e.what());
  }
  const int n_wheels = replay.wheelCount();
  VehicleWear vehicle;
  vehicle.header.frame_id = "base_link";
  vehicle.wheels.resize(static_cast<std::size_t>(n_wheels));
  for (int w = 0; w < n_wheels; ++w) {
    WheelWear& m = vehicle.wheels[static_cast<std::size_t>(w)];
    m.header.frame_id = replay.wheel(w).frame_id;
    m.wheel = replay.wheel(w).name;
    m.tire_id = replay.wheel(w).tire_id;
  }
  const std::uint64_t step = std::max<std::uint64_t>(decimation, 1);
  for (std::uint64_t k = 0; k < replay.steps(); k += step) {
    const ros::Time stamp(replay.stepTime(k));
    vehicle.header.stamp = stamp;
    vehicle.total_wear_rate_kg_per_s = vehicle.total_wear_rate_kg_per_m = vehicle.total_accumulated_loss_kg = 0.0;
    for (int w = 0; w < n_wheels; ++w) {
      const StepRecord& r = replay.records(w)[k];
      WheelWear& m = vehicle.wheels[static_cast<std::size_t>(w)];
      m.header.stamp = stamp;
      m.wear_rate_kg_per_m = r.wear_rate_kg_per_m;
      m.wear_rate_kg_per_s = r.wear_rate_kg_per_s;
      m.accumulated_loss_kg = r.accumulated_loss_kg;
      m.tread_depth_loss_m = r.tread_depth_loss_m;
      m.remaining_tread_depth_m = r.remaining_tread_depth_m;
      m.distance_m = r.distance_m;
      m.stick_fraction = r.stick_fraction;
      m.slide_fraction = r.slide_fraction;
      m.exact_stick_fraction = r.exact_stick_fraction;
      m.fx_n = r.fx_n;
      m.fy_n = r.fy_n;
      m.mz_nm = r.mz_nm;
      m.preset = presetName(r.preset);
      m.degraded = r.preset != replay.settings().model.preset;
      m.status = static_cast<std::uint8_t>(r.status);
      m.unaccounted_time_s = r.unaccounted_time_s;
      vehicle.total_wear_rate_kg_per_s += m.wear_rate_kg_per_s;
      vehicle.total_wear_rate_kg_per_m += m.wear_rate_kg_per_m;
      vehicle.total_accumulated_loss_kg += m.accumulated_loss_kg;
      bag.write(config.wear_topics[static_cast<std::size_t>(w)], stamp, m);
    }
    bag.write("/wear", stamp, vehicle);
  }
  bag.close();
}

}  // namespace tread_wear
