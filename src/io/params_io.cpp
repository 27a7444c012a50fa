#include "tread_wear/io/params_io.h"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <vector>

#include "tread_wear/model/units.h"
#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

constexpr int kFormatVersion = 1;

/// One spelling of a field: the key with its unit and the factor to SI.
struct UnitKey {
  const char* key;
  double to_si;
};

/// A numeric field of a section and the keys (one per accepted unit) that may set it.
struct FieldSpec {
  const char* field;
  std::vector<UnitKey> keys;
  double* target;
};

/// A section of the file: its numeric fields, and optionally one boolean key.
struct SectionSpec {
  const char* name;
  bool required;
  std::vector<FieldSpec> fields;
  std::vector<const char*> optional_fields;  ///< fields that keep their default when absent
  const char* bool_key = nullptr;
  bool* bool_target = nullptr;
};

std::vector<UnitKey> dimensionless(const char* key) { return {{key, 1.0}}; }
std::vector<UnitKey> length(const char* mm_key, const char* m_key) {
  return {{mm_key, units::kMillimetre}, {m_key, 1.0}};
}

class Loader {
 public:
  explicit Loader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& what) const { throw ParamsError(path_ + ": " + what); }

  void load(TireParams* params, RigGeometry* rig) {
    YAML::Node root;
    try {
      std::ifstream probe(path_);
      if (!probe) fail("cannot open the file for reading");
      root = YAML::LoadFile(path_);
    } catch (const YAML::Exception& e) {
      fail(std::string("not a readable YAML document: ") + e.what());
    }
    if (!root.IsMap()) fail("the document must be a mapping with format_version, name and the parameter sections");

    FootprintParams& f = params->footprint;
    FrictionParams& r = params->friction;
    TreadParams& t = params->tread;
    WearLawParams& w = params->wear;
    MaterialParams& m = params->material;
    const std::vector<SectionSpec> sections = {
        {"footprint", true,
         {{"a1", length("a1_mm", "a1_m"), &f.a1_m},
          {"a2", dimensionless("a2"), &f.a2},
          {"a3", length("a3_mm", "a3_m"), &f.a3_m},
          {"b", length("b_mm", "b_m"), &f.b_m},
          {"n_x", dimensionless("n_x"), &f.n_x},
          {"lambda_x", dimensionless("lambda_x"), &f.lambda_x},
          {"x_e", length("x_e_mm", "x_e_m"), &f.x_e_m},
          {"n_y", dimensionless("n_y"), &f.n_y},
          {"lambda_y", dimensionless("lambda_y"), &f.lambda_y},
          {"y_e", length("y_e_mm", "y_e_m"), &f.y_e_m}},
         {}},
        {"friction", true,
         {{"mu_0", dimensionless("mu_0"), &r.mu_0},
          {"mu_m", dimensionless("mu_m"), &r.mu_m},
          {"v_m", {{"v_m_mm_per_s", units::kMillimetrePerSecond}, {"v_m_m_per_s", 1.0}}, &r.v_m_mps},
          {"h", dimensionless("h"), &r.h},
          {"p_0", {{"p_0_MPa", units::kMegapascal}, {"p_0_Pa", 1.0}}, &r.p_0_pa},
          {"p_ref", {{"p_ref_MPa", units::kMegapascal}, {"p_ref_Pa", 1.0}}, &r.p_ref_pa},
          {"q", dimensionless("q"), &r.q}},
         {}},
        {"tread", true,
         {{"k_y0", {{"k_y0_MPa_per_mm", units::kMegapascalPerMillimetre}, {"k_y0_Pa_per_m", 1.0}}, &t.k_y0_pa_per_m},
          {"k_y1",
           {{"k_y1_MPa_per_mm_N", units::kMegapascalPerMillimetreNewton}, {"k_y1_Pa_per_m_N", 1.0}},
           &t.k_y1_pa_per_m_n},
          {"phi", dimensionless("phi"), &t.phi},
          {"c_x", {{"c_x_MPa_s_per_mm", units::kMegapascalSecondPerMillimetre}, {"c_x_Pa_s_per_m", 1.0}},
           &t.c_x_pa_s_per_m},
          {"c_y", {{"c_y_MPa_s_per_mm", units::kMegapascalSecondPerMillimetre}, {"c_y_Pa_s_per_m", 1.0}},
           &t.c_y_pa_s_per_m},
          {"m", {{"m_MPa_s2_per_mm", units::kMegapascalSecondSquaredPerMillimetre}, {"m_kg_per_m2", 1.0}},
           &t.m_kg_per_m2}},
         {}},
        {"wear", true,
         {{"w1", dimensionless("w1"), &w.w1},
          {"w2", dimensionless("w2"), &w.w2},
          {"w3", {{"w3_mg_per_s_mm2", units::kMilligramPerSecondSquareMillimetre}, {"w3_kg_per_s_m2", 1.0}},
           &w.w3_kg_per_s_m2},
          {"w4", {{"w4_mg_per_s_mm2", units::kMilligramPerSecondSquareMillimetre}, {"w4_kg_per_s_m2", 1.0}},
           &w.w4_kg_per_s_m2},
          {"T0", dimensionless("T0_degC"), &w.t0_c},
          {"sigma_T", dimensionless("sigma_T_degC"), &w.sigma_t_c},
          {"adhesion",
           {{"adhesion_mg_per_kJ", units::kMilligramPerKilojoule}, {"adhesion_kg_per_J", 1.0}},
           &w.adhesion_kg_per_j}},
         {"T0", "sigma_T", "adhesion"},
         "temperature_enabled",
         &w.temperature_enabled},
        {"material", false,
         {{"rubber_density", dimensionless("rubber_density_kg_per_m3"), &m.rubber_density_kg_per_m3},
          {"tread_depth", length("tread_depth_mm", "tread_depth_m"), &m.tread_depth_m},
          {"tread_width", length("tread_width_mm", "tread_width_m"), &m.tread_width_m},
          {"rolling_radius", length("rolling_radius_mm", "rolling_radius_m"), &m.rolling_radius_m}},
         {}},
        {"rig", false,
         {{"track_radius", length("track_radius_mm", "track_radius_m"), &rig->track_radius_m},
          {"wheel_radius", length("wheel_radius_mm", "wheel_radius_m"), &rig->wheel_radius_m},
          {"wheel_width", length("wheel_width_mm", "wheel_width_m"), &rig->wheel_width_m},
          {"rim_radius", length("rim_radius_mm", "rim_radius_m"), &rig->rim_radius_m}},
         {}},
    };

    std::set<std::string> seen;
    bool has_version = false;
    bool has_name = false;
    for (const auto& entry : root) {
      const std::string key = entry.first.as<std::string>();
      if (!seen.insert(key).second) fail("key '" + key + "' appears twice");
      if (key == "format_version") {
        const std::string text = scalarText(key, entry.second);
        if (text != std::to_string(kFormatVersion))
          fail("format_version = '" + text + "': must be " + std::to_string(kFormatVersion) +
               " (the only format this build reads)");
        has_version = true;
      } else if (key == "name") {
        params->name = scalarText(key, entry.second);
        if (params->name.empty()) fail("name = '': must be a non-empty text");
        has_name = true;
      } else {
        const SectionSpec* section = nullptr;
        for (const SectionSpec& s : sections)
          if (key == s.name) section = &s;
        if (section == nullptr) {
          std::string accepted = "format_version, name";
          for (const SectionSpec& s : sections) accepted += std::string(", ") + s.name;
          fail("unknown top-level key '" + key + "'; accepted keys: " + accepted);
        }
        loadSection(*section, entry.second);
      }
    }
    if (!has_version) fail("missing required key 'format_version' (must be " + std::to_string(kFormatVersion) + ")");
    if (!has_name) fail("missing required key 'name'");
    for (const SectionSpec& s : sections)
      if (s.required && seen.count(s.name) == 0) fail(std::string("missing required section '") + s.name + "'");

    std::string error;
    if (!params->validate(&error)) fail("invalid parameter (SI value): " + error);
    if (!rig->validate(&error)) fail("invalid parameter (SI value): " + error);
  }

 private:
  std::string scalarText(const std::string& key, const YAML::Node& node) const {
    if (!node.IsScalar()) fail("key '" + key + "': must be a single value, not a list or mapping");
    return node.Scalar();
  }

  double number(const std::string& key, const YAML::Node& node) const {
    const std::string text = scalarText(key, node);
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
      fail("key '" + key + "' = '" + text + "': must be a finite number");
    return value;
  }

  void loadSection(const SectionSpec& section, const YAML::Node& node) const {
    const std::string prefix = std::string(section.name) + ".";
    if (!node.IsMap()) fail("section '" + std::string(section.name) + "': must be a mapping of keys to values");
    std::vector<std::string> given(section.fields.size());
    std::set<std::string> seen;
    for (const auto& entry : node) {
      const std::string key = entry.first.as<std::string>();
      if (!seen.insert(key).second) fail("key '" + prefix + key + "' appears twice");
      if (section.bool_key != nullptr && key == section.bool_key) {
        const std::string text = scalarText(prefix + key, entry.second);
        if (text == "true") {
          *section.bool_target = true;
        } else if (text == "false") {
          *section.bool_target = false;
        } else {
          fail("key '" + prefix + key + "' = '" + text + "': must be true or false");
        }
        continue;
      }
      bool known = false;
      for (std::size_t i = 0; i < section.fields.size() && !known; ++i) {
        for (const UnitKey& unit_key : section.fields[i].keys) {
          if (key != unit_key.key) continue;
          if (!given[i].empty())
            fail("field '" + prefix + section.fields[i].field + "' is given twice, as '" + given[i] + "' and '" + key +
                 "': give it in one unit only");
          given[i] = key;
          *section.fields[i].target = number(prefix + key, entry.second) * unit_key.to_si;
          known = true;
          break;
        }
      }
      if (!known)
        fail("unknown key '" + prefix + key + "'; accepted keys in '" + section.name + "': " + acceptedKeys(section));
    }
    for (std::size_t i = 0; i < section.fields.size(); ++i) {
      if (!given[i].empty()) continue;
      bool optional = false;
      for (const char* name : section.optional_fields)
        optional = optional || std::string(name) == section.fields[i].field;
      if (optional) continue;
      std::string spellings;
      for (const UnitKey& unit_key : section.fields[i].keys)
        spellings += (spellings.empty() ? "" : " or ") + std::string(unit_key.key);
      fail("missing required key '" + prefix + section.fields[i].field + "' (give " + spellings + ")");
    }
  }

  static std::string acceptedKeys(const SectionSpec& section) {
    std::string keys;
    for (const FieldSpec& field : section.fields)
      for (const UnitKey& unit_key : field.keys) keys += (keys.empty() ? "" : ", ") + std::string(unit_key.key);
    if (section.bool_key != nullptr) keys += std::string(", ") + section.bool_key;
    return keys;
  }

  std::string path_;
};

}  // namespace

bool RigGeometry::validate(std::string* error) const {
  if (!(std::isfinite(track_radius_m) && track_radius_m > 0.0))
    return failValidation(error, "rig.track_radius", track_radius_m, "> 0");
  if (!(std::isfinite(wheel_radius_m) && wheel_radius_m > 0.0))
    return failValidation(error, "rig.wheel_radius", wheel_radius_m, "> 0");
  if (!(std::isfinite(wheel_width_m) && wheel_width_m > 0.0))
    return failValidation(error, "rig.wheel_width", wheel_width_m, "> 0");
  if (!(std::isfinite(rim_radius_m) && rim_radius_m > 0.0 && rim_radius_m < wheel_radius_m))
    return failValidation(error, "rig.rim_radius", rim_radius_m, "> 0 and < wheel_radius");
  return true;
}

TireParams loadTireParams(const std::string& path) {
  TireParams params;
  RigGeometry rig;
  Loader(path).load(&params, &rig);
  return params;
}

RigGeometry loadRigGeometry(const std::string& path) {
  TireParams params;
  RigGeometry rig;
  Loader(path).load(&params, &rig);
  return rig;
}

void saveTireParams(const TireParams& params, const std::string& path, const std::string& comment) {
  std::ofstream out(path);
  if (!out) throw ParamsError(path + ": cannot open the file for writing");
  std::istringstream comment_lines(comment);
  for (std::string line; std::getline(comment_lines, line);) out << "# " << line << "\n";
  out << "# tread_wear tire parameters in SI units (format: docs/parameters.md)\n";
  YAML::Emitter quoted_name;
  quoted_name << YAML::DoubleQuoted << params.name;
  out << "format_version: " << kFormatVersion << "\n";
  out << "name: " << quoted_name.c_str() << "\n";
  out << std::setprecision(17);
  const FootprintParams& f = params.footprint;
  out << "footprint:\n"
      << "  a1_m: " << f.a1_m << "\n  a2: " << f.a2 << "\n  a3_m: " << f.a3_m << "\n  b_m: " << f.b_m
      << "\n  n_x: " << f.n_x << "\n  lambda_x: " << f.lambda_x << "\n  x_e_m: " << f.x_e_m << "\n  n_y: " << f.n_y
      << "\n  lambda_y: " << f.lambda_y << "\n  y_e_m: " << f.y_e_m << "\n";
  const FrictionParams& r = params.friction;
  out << "friction:\n"
      << "  mu_0: " << r.mu_0 << "\n  mu_m: " << r.mu_m << "\n  v_m_m_per_s: " << r.v_m_mps << "\n  h: " << r.h
      << "\n  p_0_Pa: " << r.p_0_pa << "\n  p_ref_Pa: " << r.p_ref_pa << "\n  q: " << r.q << "\n";
  const TreadParams& t = params.tread;
  out << "tread:\n"
      << "  k_y0_Pa_per_m: " << t.k_y0_pa_per_m << "\n  k_y1_Pa_per_m_N: " << t.k_y1_pa_per_m_n
      << "\n  phi: " << t.phi << "\n  c_x_Pa_s_per_m: " << t.c_x_pa_s_per_m << "\n  c_y_Pa_s_per_m: "
      << t.c_y_pa_s_per_m << "\n  m_kg_per_m2: " << t.m_kg_per_m2 << "\n";
  const WearLawParams& w = params.wear;
  out << "wear:\n"
      << "  w1: " << w.w1 << "\n  w2: " << w.w2 << "\n  w3_kg_per_s_m2: " << w.w3_kg_per_s_m2
      << "\n  w4_kg_per_s_m2: " << w.w4_kg_per_s_m2
      << "\n  temperature_enabled: " << (w.temperature_enabled ? "true" : "false") << "\n  T0_degC: " << w.t0_c
      << "\n  sigma_T_degC: " << w.sigma_t_c << "\n  adhesion_kg_per_J: " << w.adhesion_kg_per_j << "\n";
  const MaterialParams& m = params.material;
  out << "material:\n"
      << "  rubber_density_kg_per_m3: " << m.rubber_density_kg_per_m3 << "\n  tread_depth_m: " << m.tread_depth_m
      << "\n  tread_width_m: " << m.tread_width_m << "\n  rolling_radius_m: " << m.rolling_radius_m << "\n";
  out.flush();
  if (!out) throw ParamsError(path + ": writing failed");
}

}  // namespace tread_wear
