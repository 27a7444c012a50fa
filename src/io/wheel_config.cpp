#include "tread_wear/io/wheel_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

/// A numeric key: where it lives in the document ("/" separates map levels, as on the parameter server) and in
/// NodeConfig. This table and NodeConfig's initialisers are the only place a key's default and unit are stated.
struct NumberKey {
  const char* key;
  const char* unit;
  const char* meaning;
  double& (*field)(NodeConfig&);
};

const NumberKey kNumberKeys[] = {
    {"update_rate_hz", "Hz",
     "rate of the update loop, in (0, 1000] and >= 2 / max_step_s; under simulated time also each wheel's step in "
     "its inputs' time; reconfigurable",
     [](NodeConfig& c) -> double& { return c.update_rate_hz; }},
    {"budget_us", "us", "time budget per wheel evaluation, >= 0 (0 = none); reconfigurable",
     [](NodeConfig& c) -> double& { return c.budget_us; }},
    {"min_speed_mps", "m/s", "low-speed threshold of the wear model, > 0",
     [](NodeConfig& c) -> double& { return c.model.min_speed_mps; }},
    {"stale_timeout_s", "s", "an older input is stale: not evaluated, not integrated",
     [](NodeConfig& c) -> double& { return c.estimator.stale_timeout_s; }},
    {"max_step_s", "s", "a longer forward clock step is a time jump, > stale_timeout_s",
     [](NodeConfig& c) -> double& { return c.estimator.max_step_s; }},
    {"limits/max_load_n", "N", "larger loads are rejected",
     [](NodeConfig& c) -> double& { return c.estimator.limits.max_load_n; }},
    {"limits/max_abs_slip_angle_rad", "rad", "larger |slip angle| is rejected, < pi/2",
     [](NodeConfig& c) -> double& { return c.estimator.limits.max_abs_slip_angle_rad; }},
    {"limits/max_abs_slip_ratio", "-", "larger |slip ratio| is rejected, <= 1",
     [](NodeConfig& c) -> double& { return c.estimator.limits.max_abs_slip_ratio; }},
    {"limits/max_abs_path_curvature_per_m", "1/m", "larger |path curvature| is rejected",
     [](NodeConfig& c) -> double& { return c.estimator.limits.max_abs_path_curvature_per_m; }},
    {"limits/max_speed_mps", "m/s", "larger speeds are rejected",
     [](NodeConfig& c) -> double& { return c.estimator.limits.max_speed_mps; }},
    {"limits/min_temperature_c", "degC", "lower tread temperatures are rejected",
     [](NodeConfig& c) -> double& { return c.estimator.limits.min_temperature_c; }},
    {"limits/max_temperature_c", "degC", "higher tread temperatures are rejected",
     [](NodeConfig& c) -> double& { return c.estimator.limits.max_temperature_c; }},
    {"save_interval_s", "s", "wall-clock period of state saves, > 0",
     [](NodeConfig& c) -> double& { return c.save_interval_s; }},
    {"marker_rate_hz", "Hz", "rviz marker rate, in [0, update_rate_hz] (0 = off)",
     [](NodeConfig& c) -> double& { return c.marker_rate_hz; }},
};

/// A free-text key.
struct StringKey {
  const char* key;
  const char* meaning;
  std::string& (*field)(NodeConfig&);
};

const StringKey kStringKeys[] = {
    {"state_file", "persistence file; empty = no persistence", [](NodeConfig& c) -> std::string& { return c.state_file; }},
    {"base_frame", "frame of the aggregate wear message and of wheel positions",
     [](NodeConfig& c) -> std::string& { return c.base_frame; }},
    {"config_dir", "start of relative tire_params paths (empty = working directory)",
     [](NodeConfig& c) -> std::string& { return c.config_dir; }},
};

std::string text(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

bool fail(std::string* error, const std::string& key, const std::string& value, const std::string& constraint) {
  if (error != nullptr) *error = key + " = " + value + ": must be " + constraint;
  return false;
}

ConfigValue value(ConfigValue::Type type) {
  ConfigValue v;
  v.type = type;
  return v;
}

/// The value at a "/"-separated path, or nullptr when a level is absent; false (with *error) when a level on the
/// way is not a map.
bool lookup(const ConfigValue& doc, const std::string& path, const ConfigValue** out, std::string* error) {
  const ConfigValue* at = &doc;
  std::size_t begin = 0;
  while (true) {
    if (at->type != ConfigValue::Type::kMap)
      return fail(error, path.substr(0, begin == 0 ? 0 : begin - 1), at->text(), "a map");
    const std::size_t slash = path.find('/', begin);
    const auto it = at->map.find(path.substr(begin, slash == std::string::npos ? std::string::npos : slash - begin));
    if (it == at->map.end()) {
      *out = nullptr;
      return true;
    }
    at = &it->second;
    if (slash == std::string::npos) break;
    begin = slash + 1;
  }
  *out = at;
  return true;
}

bool readString(const ConfigValue& map, const std::string& where, const char* key, std::string* out,
                std::string* error) {
  const auto it = map.map.find(key);
  if (it == map.map.end()) return true;
  if (it->second.type != ConfigValue::Type::kString) return fail(error, where + key, it->second.text(), "a string");
  *out = it->second.string;
  return true;
}

bool readWheel(const ConfigValue& w, const std::string& where, const std::string& config_dir, WheelConfig* wc,
               std::string* error) {
  if (w.type != ConfigValue::Type::kMap) return fail(error, where, w.text(), "a map");
  const std::string prefix = where + ".";
  if (!w.map.count("name")) return fail(error, prefix + "name", "(missing)", "given");
  if (!readString(w, prefix, "name", &wc->name, error)) return false;
  if (!w.map.count("tire_params")) return fail(error, prefix + "tire_params", "(missing)", "given");
  wc->frame_id = wc->name;
  const std::string topics = "wheels/" + wc->name + "/";
  wc->load_topic = topics + "load";
  wc->slip_topic = topics + "slip";
  wc->speed_topic = topics + "speed";
  wc->temperature_topic = topics + "tread_temperature";
  wc->wear_topic = topics + "wear";
  if (!readString(w, prefix, "frame_id", &wc->frame_id, error) ||
      !readString(w, prefix, "tire_params", &wc->tire_params, error) ||
      !readString(w, prefix, "tire_id", &wc->tire_id, error) ||
      !readString(w, prefix, "load_topic", &wc->load_topic, error) ||
      !readString(w, prefix, "slip_topic", &wc->slip_topic, error) ||
      !readString(w, prefix, "speed_topic", &wc->speed_topic, error) ||
      !readString(w, prefix, "temperature_topic", &wc->temperature_topic, error) ||
      !readString(w, prefix, "wear_topic", &wc->wear_topic, error))
    return false;
  const auto position = w.map.find("position_m");
  if (position != w.map.end()) {
    const ConfigValue& p = position->second;
    if (p.type != ConfigValue::Type::kList || p.list.size() != 3 ||
        !std::all_of(p.list.begin(), p.list.end(), [](const ConfigValue& v) { return v.type == ConfigValue::Type::kNumber; }))
      return fail(error, prefix + "position_m", p.text(), "a list of three numbers [x, y, z] [m]");
    for (std::size_t k = 0; k < 3; ++k) wc->position_m[k] = p.list[k].number;
    wc->has_position = true;
  }
  if (!wc->tire_params.empty() && wc->tire_params[0] != '/' && !config_dir.empty())
    wc->tire_params = config_dir + "/" + wc->tire_params;
  return true;
}

/// YAML 1.1 booleans as rosparam's loader reads them (not yaml-cpp's single letters y/n, which are names).
bool yamlBool(const std::string& s, bool* v) {
  std::string lower(s);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower == "true" || lower == "yes" || lower == "on") *v = true;
  else if (lower == "false" || lower == "no" || lower == "off") *v = false;
  else return false;
  return true;
}

/// A YAML node as the tree readNodeConfig() reads: plain scalars become null, booleans or numbers when they read as
/// such; quoted ones stay strings.
ConfigValue fromYaml(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null: return ConfigValue();
    case YAML::NodeType::Sequence: {
      ConfigValue list = value(ConfigValue::Type::kList);
      for (const YAML::Node& item : node) list.list.push_back(fromYaml(item));
      return list;
    }
    case YAML::NodeType::Map: {
      ConfigValue map = value(ConfigValue::Type::kMap);
      for (const auto& kv : node) map.map[kv.first.as<std::string>()] = fromYaml(kv.second);
      return map;
    }
    case YAML::NodeType::Scalar: break;
  }
  ConfigValue v = value(ConfigValue::Type::kString);
  v.string = node.Scalar();
  if (node.Tag() == "!") return v;  // quoted
  if (yamlBool(v.string, &v.boolean)) {
    v.type = ConfigValue::Type::kBool;
  } else if (YAML::convert<double>::decode(node, v.number)) {
    v.type = ConfigValue::Type::kNumber;
  }
  return v;
}

}  // namespace

std::string ConfigValue::text() const {
  switch (type) {
    case Type::kNull: return "null";
    case Type::kBool: return boolean ? "true" : "false";
    case Type::kNumber: return tread_wear::text(number);
    case Type::kString: return "\"" + string + "\"";
    case Type::kList: {
      std::string out = "[";
      for (std::size_t i = 0; i < list.size(); ++i) out += (i > 0 ? ", " : "") + list[i].text();
      return out + "]";
    }
    case Type::kMap: {
      std::string out = "{";
      for (const auto& kv : map) out += (out.size() > 1 ? ", " : "") + kv.first + ": " + kv.second.text();
      return out + "}";
    }
  }
  return "";
}

bool NodeConfig::validate(std::string* error) const {
  if (!(update_rate_hz > 0.0 && update_rate_hz <= 1000.0))
    return failValidation(error, "update_rate_hz", update_rate_hz, "in (0, 1000] [Hz]");
  if (!(budget_us >= 0.0) || !std::isfinite(budget_us))
    return failValidation(error, "budget_us", budget_us, "finite and >= 0 [us]");
  if (!model.validate(error)) return false;
  std::string sub;
  if (!estimator.validate(&sub)) {
    // The estimator names a limit "limits.<field>"; the document's key is "limits/<field>".
    if (sub.rfind("limits.", 0) == 0) sub[6] = '/';
    if (error != nullptr) *error = sub;
    return false;
  }
  // The node's timer fires late by up to a period under load (and in whole /clock ticks under sim time): a step
  // of about one period must never count as a clock jump, or every other interval goes unintegrated.
  if (!(update_rate_hz * estimator.max_step_s >= 2.0))
    return failValidation(error, "update_rate_hz", update_rate_hz,
                          ">= 2 / max_step_s = " + text(2.0 / estimator.max_step_s) +
                              " Hz, so that a late update is not a clock jump");
  if (!(marker_rate_hz >= 0.0 && marker_rate_hz <= update_rate_hz))
    return failValidation(error, "marker_rate_hz", marker_rate_hz, "in [0, update_rate_hz = " +
                                                                        text(update_rate_hz) + "] [Hz]");
  if (!(save_interval_s > 0.0) || !std::isfinite(save_interval_s))
    return failValidation(error, "save_interval_s", save_interval_s, "finite and > 0 [s]");
  if (base_frame.empty()) return fail(error, "base_frame", "''", "non-empty");
  if (wheels.empty()) return fail(error, "wheels", "[]", "a non-empty list");
  std::set<std::string> names;
  for (const WheelConfig& w : wheels) {
    if (w.name.empty()) return fail(error, "wheels[].name", "''", "non-empty");
    if (!names.insert(w.name).second) return fail(error, "wheels[].name", w.name, "unique");
    const std::string where = "wheels[" + w.name + "].";
    if (w.frame_id.empty()) return fail(error, where + "frame_id", "''", "non-empty");
    if (w.tire_params.empty()) return fail(error, where + "tire_params", "''", "a file path");
    if (w.tire_id.empty() || w.tire_id.size() > kMaxTireIdLength)
      return fail(error, where + "tire_id", "'" + w.tire_id + "'",
                  "1 to " + std::to_string(kMaxTireIdLength) + " characters");
    for (const std::string* topic : {&w.load_topic, &w.slip_topic, &w.speed_topic, &w.temperature_topic,
                                     &w.wear_topic})
      if (topic->empty()) return fail(error, where + "*_topic", "''", "a topic name");
  }
  return true;
}

std::string NodeConfig::describe() const {
  NodeConfig copy = *this;  // the key table reaches fields through non-const references
  std::ostringstream s;
  s.precision(10);
  for (const NumberKey& k : kNumberKeys) s << k.key << ": " << k.field(copy) << " [" << k.unit << "]\n";
  s << "preset: " << presetName(model.preset) << "\n"
    << "turn_slip_orientation: " << orientationName(model.orientation) << "\n";
  for (const StringKey& k : kStringKeys) s << k.key << ": " << k.field(copy) << "\n";
  for (const WheelConfig& w : wheels) {
    s << "wheel " << w.name << ": frame_id " << w.frame_id << ", tire_params " << w.tire_params << ", tire_id "
      << w.tire_id << ", topics " << w.load_topic << " " << w.slip_topic << " " << w.speed_topic << " "
      << w.temperature_topic << " -> " << w.wear_topic;
    if (w.has_position)
      s << ", position_m [" << w.position_m[0] << ", " << w.position_m[1] << ", " << w.position_m[2] << "]";
    s << "\n";
  }
  return s.str();
}

bool readNodeConfig(const ConfigValue& document, const std::string& default_config_dir, NodeConfig* config,
                    std::string* error) {
  if (document.type != ConfigValue::Type::kMap) return fail(error, "(document)", document.text(), "a map of keys");
  NodeConfig c;
  c.config_dir = default_config_dir;
  const ConfigValue* v = nullptr;
  for (const NumberKey& k : kNumberKeys) {
    if (!lookup(document, k.key, &v, error)) return false;
    if (v == nullptr) continue;
    if (v->type != ConfigValue::Type::kNumber)
      return fail(error, k.key, v->text(), std::string("a number [") + k.unit + "]");
    k.field(c) = v->number;
  }
  for (const StringKey& k : kStringKeys) {
    if (!lookup(document, k.key, &v, error)) return false;
    if (v == nullptr) continue;
    if (v->type != ConfigValue::Type::kString) return fail(error, k.key, v->text(), "a string");
    k.field(c) = v->string;
  }
  if (!lookup(document, "preset", &v, error)) return false;
  if (v != nullptr && !(v->type == ConfigValue::Type::kString && parsePreset(v->string, &c.model.preset)))
    return fail(error, "preset", v->text(), kPresetChoices);
  if (!lookup(document, "turn_slip_orientation", &v, error)) return false;
  if (v != nullptr && !(v->type == ConfigValue::Type::kString && parseOrientation(v->string, &c.model.orientation)))
    return fail(error, "turn_slip_orientation", v->text(), "literal or flipped");
  if (!lookup(document, "wheels", &v, error)) return false;
  if (v == nullptr) return fail(error, "wheels", "(missing)", "a list of wheels");
  if (v->type != ConfigValue::Type::kList) return fail(error, "wheels", v->text(), "a list of wheels");
  for (std::size_t i = 0; i < v->list.size(); ++i) {
    WheelConfig wc;
    if (!readWheel(v->list[i], "wheels[" + std::to_string(i) + "]", c.config_dir, &wc, error)) return false;
    c.wheels.push_back(wc);
  }
  if (!c.validate(error)) return false;
  *config = std::move(c);
  return true;
}

ConfigValue loadConfigDocument(const std::string& path) {
  auto failure = [&](const std::string& what) { return std::runtime_error(path + ": " + what); };
  try {
    if (!std::ifstream(path)) throw failure("cannot open the file for reading");
    return fromYaml(YAML::LoadFile(path));
  } catch (const YAML::Exception& e) {
    throw failure(std::string("not a readable YAML document: ") + e.what());
  }
}

NodeConfig loadNodeConfigFile(const std::string& path) {
  auto failure = [&](const std::string& what) { return std::runtime_error(path + ": " + what); };
  const ConfigValue document = loadConfigDocument(path);
  const std::size_t slash = path.find_last_of('/');
  const std::string directory = slash == std::string::npos ? "." : path.substr(0, slash);
  NodeConfig config;
  std::string error;
  if (!readNodeConfig(document, directory, &config, &error)) throw failure(error);
  return config;
}

std::string nodeConfigKeysHelp() {
  NodeConfig defaults;
  std::ostringstream s;
  s.precision(10);
  for (const NumberKey& k : kNumberKeys)
    s << "  " << k.key << " [" << k.unit << "] = " << k.field(defaults) << ": " << k.meaning << "\n";
  s << "  preset = " << presetName(defaults.model.preset) << ": finest model preset, " << kPresetChoices
    << "; reconfigurable\n"
    << "  turn_slip_orientation = " << orientationName(defaults.model.orientation)
    << ": slip angle vs path curve, literal or flipped\n";
  for (const StringKey& k : kStringKeys)
    s << "  " << k.key << " = '" << k.field(defaults) << "': " << k.meaning << "\n";
  s << "  wheels (required): list of {name, tire_params, frame_id (= name), tire_id (= unknown), position_m [x, y, z] "
       "[m], load_topic, slip_topic, speed_topic, temperature_topic, wear_topic (= wheels/<name>/...)}\n";
  return s.str();
}

}  // namespace tread_wear
