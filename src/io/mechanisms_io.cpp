#include "tread_wear/io/mechanisms_io.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace tread_wear {
namespace {

const std::set<std::string> kMechanismKeys = {"name",    "statement",  "physical",   "parameters",
                                              "affects", "covariates", "expression", "test_magnitudes"};
const std::set<std::string> kParameterKeys = {"name", "unit", "lower", "upper", "no_effect", "initial"};

std::string list(const std::set<std::string>& keys) {
  std::string s;
  for (const std::string& k : keys) s += (s.empty() ? "" : ", ") + k;
  return s;
}

bool isIdentifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const YAML::Node& at, const std::string& what) const { fail(lineOf(at), what); }
  [[noreturn]] void fail(int line, const std::string& what) const {
    throw MechanismFileError(source_ + ":" + std::to_string(line) + ": " + what);
  }
  static int lineOf(const YAML::Node& n) { return n.Mark().line + 1; }

  MechanismFile parse(const std::string& text) {
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw MechanismFileError(source_ + ":" + std::to_string(e.mark.line + 1) +
                               ": not a readable YAML document: " + e.msg);
    }
    if (!root.IsMap()) throw MechanismFileError(source_ + ":1: the document must be a mapping with the key mechanisms");
    for (const auto& kv : root)
      if (kv.first.as<std::string>() != "mechanisms")
        fail(kv.first, "unknown key '" + kv.first.as<std::string>() + "' (the document has one key: mechanisms)");
    const YAML::Node list_node = root["mechanisms"];
    if (!list_node) throw MechanismFileError(source_ + ":1: missing key 'mechanisms'");
    if (!list_node.IsSequence() || list_node.size() == 0)
      fail(list_node, "'mechanisms' must be a non-empty list of mechanisms");
    MechanismFile file;
    file.path = source_;
    std::set<std::string> names;
    for (const YAML::Node& m : list_node) {
      MechanismSpec spec = mechanism(m);
      if (!names.insert(spec.name).second)
        fail(spec.name_line, "mechanism name '" + spec.name + "' is used twice in this file");
      file.mechanisms.push_back(std::move(spec));
    }
    return file;
  }

 private:
  void checkKeys(const YAML::Node& map, const std::set<std::string>& known, const std::string& what) const {
    for (const auto& kv : map) {
      const std::string key = kv.first.as<std::string>();
      if (!known.count(key)) fail(kv.first, "unknown key '" + key + "' in " + what + " (known: " + list(known) + ")");
    }
  }

  YAML::Node required(const YAML::Node& map, const std::string& key, const std::string& what) const {
    const YAML::Node n = map[key];
    if (!n) fail(map, what + ": missing field '" + key + "'");
    return n;
  }

  std::string text(const YAML::Node& n, const std::string& field) const {
    if (!n.IsScalar() || n.Scalar().empty()) fail(n, field + " must be a non-empty text");
    return n.Scalar();
  }

  std::string identifier(const YAML::Node& n, const std::string& field) const {
    const std::string s = text(n, field);
    if (!isIdentifier(s))
      fail(n, field + " = '" + s + "' must be an identifier (letters, digits and _, not starting with a digit)");
    return s;
  }

  double number(const YAML::Node& n, const std::string& field) const {
    if (!n.IsScalar()) fail(n, field + " must be a number");
    std::istringstream in(n.Scalar());
    double v;
    in >> v;
    if (!in || !in.eof() || !std::isfinite(v)) fail(n, field + " = '" + n.Scalar() + "' must be a finite number");
    return v;
  }

  std::vector<std::string> identifiers(const YAML::Node& n, const std::string& field, std::vector<int>* lines) const {
    if (!n.IsSequence()) fail(n, field + " must be a list");
    std::vector<std::string> out;
    for (const YAML::Node& item : n) {
      out.push_back(identifier(item, field + " entry"));
      lines->push_back(lineOf(item));
    }
    return out;
  }

  MechanismParameterSpec parameter(const YAML::Node& p, const std::string& owner) const {
    const std::string what = "parameter of '" + owner + "'";
    if (!p.IsMap()) fail(p, what + " must be a mapping with " + list(kParameterKeys));
    checkKeys(p, kParameterKeys, what);
    MechanismParameterSpec s;
    s.line = lineOf(p);
    s.name = identifier(required(p, "name", what), "parameter name");
    const std::string where = "parameter '" + s.name + "' of '" + owner + "'";
    s.unit = text(required(p, "unit", where), where + ": unit");
    s.lower = number(required(p, "lower", where), where + ": lower");
    s.upper = number(required(p, "upper", where), where + ": upper");
    const YAML::Node no_effect = required(p, "no_effect", where);
    s.no_effect = number(no_effect, where + ": no_effect");
    if (!(s.lower < s.upper))
      fail(p["upper"], where + ": lower = " + p["lower"].Scalar() + " must be < upper = " + p["upper"].Scalar());
    if (!(s.no_effect >= s.lower && s.no_effect <= s.upper))
      fail(no_effect, where + ": no_effect = " + no_effect.Scalar() + " must be in [lower, upper] = [" +
                          p["lower"].Scalar() + ", " + p["upper"].Scalar() + "]");
    if (const YAML::Node initial = p["initial"]) {
      s.initial = number(initial, where + ": initial");
      if (!(s.initial >= s.lower && s.initial <= s.upper))
        fail(initial, where + ": initial = " + initial.Scalar() + " must be in [lower, upper] = [" +
                          p["lower"].Scalar() + ", " + p["upper"].Scalar() + "]");
    }
    return s;
  }

  MechanismSpec mechanism(const YAML::Node& m) const {
    if (!m.IsMap()) fail(m, "a mechanism must be a mapping with " + list(kMechanismKeys));
    MechanismSpec spec;
    spec.line = lineOf(m);
    checkKeys(m, kMechanismKeys, "a mechanism");
    const YAML::Node name = required(m, "name", "mechanism");
    spec.name = identifier(name, "name");
    spec.name_line = lineOf(name);
    const std::string what = "mechanism '" + spec.name + "'";
    const YAML::Node statement = required(m, "statement", what);
    spec.statement = text(statement, what + ": statement");
    if (spec.statement.find('\n') != std::string::npos) fail(statement, what + ": the statement must be one line");
    if (const YAML::Node physical = m["physical"]) {
      if (!physical.IsScalar() || (physical.Scalar() != "true" && physical.Scalar() != "false"))
        fail(physical, what + ": physical must be true or false");
      spec.physical = physical.Scalar() == "true";
    }
    const YAML::Node params = required(m, "parameters", what);
    if (!params.IsSequence() || params.size() == 0)
      fail(params, what + ": parameters must be a non-empty list (the first is the size of the effect)");
    std::set<std::string> names;
    for (const YAML::Node& p : params) {
      spec.parameters.push_back(parameter(p, spec.name));
      if (!names.insert(spec.parameters.back().name).second)
        fail(p, what + ": parameter '" + spec.parameters.back().name + "' is listed twice");
    }
    const YAML::Node affects = required(m, "affects", what);
    spec.affects = identifiers(affects, what + ": affects", &spec.affects_lines);
    if (spec.affects.empty()) fail(affects, what + ": affects must name at least one output");
    if (const YAML::Node covariates = m["covariates"])
      spec.covariates = identifiers(covariates, what + ": covariates", &spec.covariates_lines);
    const YAML::Node expression = required(m, "expression", what);
    spec.expression = text(expression, what + ": expression");
    spec.expression_line = lineOf(expression);
    if (const YAML::Node magnitudes = m["test_magnitudes"]) {
      const MechanismParameterSpec& size = spec.parameters.front();
      if (!magnitudes.IsSequence() || magnitudes.size() < 1 || magnitudes.size() > 2)
        fail(magnitudes, what + ": test_magnitudes must list one or two values of " + size.name + " (small, large)");
      for (const YAML::Node& v : magnitudes) {
        const double x = number(v, what + ": test_magnitudes entry");
        if (!(x >= size.lower && x <= size.upper) || x == size.no_effect)
          fail(v, what + ": test_magnitudes entry " + v.Scalar() + " must be a value of " + size.name +
                      " in [lower, upper] other than its no_effect");
        spec.test_magnitudes.push_back(x);
      }
    }
    return spec;
  }

  std::string source_;
};

}  // namespace

MechanismFile parseMechanismFile(const std::string& text, const std::string& source) {
  return Parser(source).parse(text);
}

MechanismFile readMechanismFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MechanismFileError(path + ": cannot open the file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return parseMechanismFile(text.str(), path);
}

}  // namespace tread_wear
