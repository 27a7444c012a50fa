#include "tread_wear/io/state_store.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace tread_wear {
namespace {

double wallNow_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string utcStamp() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y%m%dT%H%M%SZ", &tm);
  return buf;
}

std::string errnoText(const std::string& step, const std::string& path) {
  return step + " " + path + ": " + std::strerror(errno);
}

std::string directoryOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

bool nonNegativeFinite(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

const WheelRecord* StateFile::find(const std::string& name) const {
  for (const WheelRecord& w : wheels)
    if (w.name == name) return &w;
  return nullptr;
}

WheelRecord* StateFile::find(const std::string& name) {
  for (WheelRecord& w : wheels)
    if (w.name == name) return &w;
  return nullptr;
}

const char* loadStatusName(LoadStatus status) {
  switch (status) {
    case LoadStatus::kLoaded: return "loaded";
    case LoadStatus::kMissing: return "missing";
    case LoadStatus::kCorrupt: return "corrupt";
    case LoadStatus::kIncompatible: return "incompatible";
    case LoadStatus::kIoError: return "io_error";
  }
  return "unknown";
}

std::string StateStore::toJson(const StateFile& state) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["saved_unix_s"] = state.saved_unix_s;
  j["wheels"] = nlohmann::json::array();
  for (const WheelRecord& w : state.wheels) {
    j["wheels"].push_back({{"name", w.name},
                           {"tire_id", w.tire_id},
                           {"accumulated_loss_kg", w.accumulated_loss_kg},
                           {"distance_m", w.distance_m},
                           {"reset_unix_s", w.reset_unix_s}});
  }
  // nlohmann writes doubles with round-trip precision: a saved value is restored exactly.
  return j.dump(2) + "\n";
}

bool StateStore::fromJson(const std::string& text, StateFile* state, std::string* error, bool* incompatible) {
  *incompatible = false;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    *error = std::string("not valid JSON: ") + e.what();
    return false;
  }
  if (!j.is_object() || !j.contains("format") || !j["format"].is_string() || j["format"] != kFormat) {
    *incompatible = true;
    *error = std::string("not a tread_wear state file (\"format\" is not \"") + kFormat + "\")";
    return false;
  }
  if (!j.contains("version") || !j["version"].is_number_integer() || j["version"].get<int>() != kVersion) {
    *incompatible = true;
    *error = "version " + (j.contains("version") ? j["version"].dump() : std::string("(missing)")) +
             " is not the supported version " + std::to_string(kVersion);
    return false;
  }
  try {
    StateFile s;
    s.saved_unix_s = j.at("saved_unix_s").get<double>();
    std::set<std::string> names;
    for (const nlohmann::json& w : j.at("wheels")) {
      WheelRecord r;
      r.name = w.at("name").get<std::string>();
      r.tire_id = w.at("tire_id").get<std::string>();
      r.accumulated_loss_kg = w.at("accumulated_loss_kg").get<double>();
      r.distance_m = w.at("distance_m").get<double>();
      r.reset_unix_s = w.value("reset_unix_s", 0.0);
      if (r.name.empty()) {
        *error = "a wheel has an empty name";
        return false;
      }
      if (!names.insert(r.name).second) {
        *error = "wheel '" + r.name + "' appears twice";
        return false;
      }
      if (!nonNegativeFinite(r.accumulated_loss_kg)) {
        *error = "wheel '" + r.name + "': accumulated_loss_kg = " + std::to_string(r.accumulated_loss_kg) +
                 ": must be finite and >= 0";
        return false;
      }
      if (!nonNegativeFinite(r.distance_m)) {
        *error = "wheel '" + r.name + "': distance_m = " + std::to_string(r.distance_m) + ": must be finite and >= 0";
        return false;
      }
      s.wheels.push_back(std::move(r));
    }
    *state = std::move(s);
  } catch (const nlohmann::json::exception& e) {
    *error = std::string("missing or mistyped field: ") + e.what();
    return false;
  }
  return true;
}

LoadResult StateStore::load() const {
  LoadResult result;
  struct stat st;
  if (::stat(path_.c_str(), &st) != 0) {
    if (errno == ENOENT) {
      result.status = LoadStatus::kMissing;
      result.message = "no state file at " + path_ + ": starting from zero";
      return result;
    }
    result.status = LoadStatus::kIoError;
    result.message = errnoText("cannot stat", path_);
    return result;
  }
  // A directory (or a device, a pipe) at the path is no state file at all, corrupt or otherwise: reading it would
  // look like empty content, and moving it aside would move someone else's data. Leave it and say what it is.
  if (!S_ISREG(st.st_mode)) {
    result.status = LoadStatus::kIoError;
    result.message = "state file path " + path_ + " is " + (S_ISDIR(st.st_mode) ? "a directory" : "not a regular file") +
                     ", not a state file";
    return result;
  }
  std::ifstream in(path_, std::ios::binary);
  if (!in) {
    result.status = LoadStatus::kIoError;
    result.message = errnoText("cannot open", path_);
    return result;
  }
  std::ostringstream buf;
  buf << in.rdbuf();
  std::string error;
  bool incompatible = false;
  if (fromJson(buf.str(), &result.state, &error, &incompatible)) {
    result.status = LoadStatus::kLoaded;
    result.message = "restored " + std::to_string(result.state.wheels.size()) + " wheel(s) from " + path_;
    return result;
  }
  result.state = StateFile();
  const std::string kind = incompatible ? "incompatible" : "corrupt";
  const std::string aside = path_ + "." + kind + "-" + utcStamp();
  if (std::rename(path_.c_str(), aside.c_str()) != 0) {
    result.status = LoadStatus::kIoError;
    result.message = "state file " + path_ + " is " + kind + " (" + error + ") and could not be moved aside: " +
                     std::strerror(errno);
    return result;
  }
  result.status = incompatible ? LoadStatus::kIncompatible : LoadStatus::kCorrupt;
  result.moved_to = aside;
  result.message = "state file " + path_ + " is " + kind + " (" + error + "); moved to " + aside;
  return result;
}

bool StateStore::save(const StateFile& state, std::string* error) const {
  StateFile stamped = state;
  stamped.saved_unix_s = wallNow_s();
  const std::string text = toJson(stamped);
  const std::string tmp = path_ + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (error) *error = errnoText("open", tmp);
    return false;
  }
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (error) *error = errnoText("write", tmp);
      ::close(fd);
      return false;
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    if (error) *error = errnoText("fsync", tmp);
    ::close(fd);
    return false;
  }
  if (::close(fd) != 0) {
    if (error) *error = errnoText("close", tmp);
    return false;
  }
  if (std::rename(tmp.c_str(), path_.c_str()) != 0) {
    if (error) *error = errnoText("rename to " + path_ + " from", tmp);
    return false;
  }
  // Make the rename itself durable.
  const std::string dir = directoryOf(path_);
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  return true;
}

}  // namespace tread_wear
