#include "tread_wear/io/rolling_radius_store.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace tread_wear {
namespace {

constexpr const char* kFormat = "tread_wear_rolling_radii";
constexpr int kVersion = 1;

std::string errnoText(const std::string& step, const std::string& path) {
  return step + " " + path + ": " + std::strerror(errno);
}

}  // namespace

const char* radiusLoadStatusName(RadiusLoadStatus status) {
  switch (status) {
    case RadiusLoadStatus::kLoaded: return "loaded";
    case RadiusLoadStatus::kMissing: return "missing";
    case RadiusLoadStatus::kInvalid: return "invalid";
  }
  return "unknown";
}

std::string rollingRadiiJson(const std::array<std::string, kWheelCount>& names,
                             const std::array<RollingRadiusState, kWheelCount>& state, double saved_unix_s) {
  nlohmann::json doc;
  doc["format"] = kFormat;
  doc["version"] = kVersion;
  doc["saved_unix_s"] = saved_unix_s;
  doc["wheels"] = nlohmann::json::array();
  for (int i = 0; i < kWheelCount; ++i)
    doc["wheels"].push_back({{"name", names[i]},
                             {"radius_m", state[i].radius_m},
                             {"learned_distance_m", state[i].learned_distance_m}});
  return doc.dump(2) + "\n";
}

bool parseRollingRadiiJson(const std::string& text, const std::array<std::string, kWheelCount>& names,
                           std::array<RollingRadiusState, kWheelCount>* state, std::string* error) {
  try {
    const nlohmann::json doc = nlohmann::json::parse(text);
    if (doc.value("format", std::string()) != kFormat || doc.value("version", 0) != kVersion) {
      *error = std::string("not a ") + kFormat + " version " + std::to_string(kVersion) + " document";
      return false;
    }
    std::array<RollingRadiusState, kWheelCount> out{};
    for (int i = 0; i < kWheelCount; ++i) {
      bool found = false;
      for (const nlohmann::json& w : doc.at("wheels")) {
        if (w.at("name").get<std::string>() != names[i]) continue;
        out[i].radius_m = w.at("radius_m").get<double>();
        out[i].learned_distance_m = w.at("learned_distance_m").get<double>();
        found = true;
      }
      if (!found) {
        *error = "wheel " + names[i] + " missing";
        return false;
      }
      if (!std::isfinite(out[i].radius_m) || out[i].radius_m <= 0.0 || !std::isfinite(out[i].learned_distance_m) ||
          out[i].learned_distance_m < 0.0) {
        *error = "wheel " + names[i] + ": radius_m must be finite and > 0, learned_distance_m finite and >= 0";
        return false;
      }
    }
    *state = out;
    return true;
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
}

RadiusLoadStatus loadRollingRadii(const std::string& path, const std::array<std::string, kWheelCount>& names,
                                  std::array<RollingRadiusState, kWheelCount>* state, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (errno == ENOENT) return RadiusLoadStatus::kMissing;
    *error = errnoText("open", path);
    return RadiusLoadStatus::kInvalid;
  }
  std::stringstream text;
  text << in.rdbuf();
  if (!parseRollingRadiiJson(text.str(), names, state, error)) {
    *error = path + ": " + *error;
    return RadiusLoadStatus::kInvalid;
  }
  return RadiusLoadStatus::kLoaded;
}

bool saveRollingRadii(const std::string& path, const std::array<std::string, kWheelCount>& names,
                      const std::array<RollingRadiusState, kWheelCount>& state, double saved_unix_s,
                      std::string* error) {
  const std::string text = rollingRadiiJson(names, state, saved_unix_s);
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    *error = errnoText("open", tmp);
    return false;
  }
  const char* p = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      *error = errnoText("write", tmp);
      ::close(fd);
      return false;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    *error = errnoText("fsync", tmp);
    ::close(fd);
    return false;
  }
  ::close(fd);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = errnoText("rename", tmp);
    return false;
  }
  return true;
}

}  // namespace tread_wear
