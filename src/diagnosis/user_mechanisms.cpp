#include "tread_wear/diagnosis/user_mechanisms.h"

#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>

namespace tread_wear {
namespace diagnosis {
namespace {

/// The model's outputs as an expression reads them.
constexpr const char* kOutputVariable = "output";
constexpr const char* kSideForceVariable = "side_force_n";
constexpr const char* kWearVariable = "wear_kg_per_m";
/// An expression at its no-effect values must give the model's output back to this relative tolerance [-].
constexpr double kNoEffectTolerance = 1e-9;

struct OperatingVariable {
  const char* name;
  std::function<double(const DiagnosisRun&)> value;
};

const std::vector<OperatingVariable>& operatingTable() {
  static const std::vector<OperatingVariable> table = {
      {"load_n", [](const DiagnosisRun& r) { return r.op.load_n; }},
      {"slip_angle_rad", [](const DiagnosisRun& r) { return r.op.slip_angle_rad; }},
      {"speed_mps", [](const DiagnosisRun& r) { return r.op.speed_mps; }},
      {"slip_ratio", [](const DiagnosisRun& r) { return r.op.slip_ratio; }},
      {"path_curvature_per_m", [](const DiagnosisRun& r) { return r.op.path_curvature_per_m; }},
      {"tread_temperature_c", [](const DiagnosisRun& r) { return r.tread_temperature_c; }},
      {"load_std_n", [](const DiagnosisRun& r) { return r.load_std_n; }},
      {"sliding_distance_m", [](const DiagnosisRun& r) { return r.sliding_distance_m; }},
      {"cumulative_sliding_m", [](const DiagnosisRun& r) { return r.cumulative_sliding_m; }},
      {"run_order", [](const DiagnosisRun& r) { return r.run_order >= 0 ? double(r.run_order) : NAN; }},
      {"cycle_id", [](const DiagnosisRun& r) { return r.cycle >= 0 ? double(r.cycle) : NAN; }},
  };
  return table;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

/// A muparser over the variables of one mechanism, each bound to a slot of `slots`: the three output variables,
/// the operating variables, the declared covariates, then the parameters (slot order = names()).
class BoundParser {
 public:
  BoundParser(const std::vector<std::string>& covariates, const std::vector<TermParameterSpec>& parameters) {
    names_ = {kOutputVariable, kSideForceVariable, kWearVariable};
    for (const OperatingVariable& v : operatingTable()) names_.push_back(v.name);
    names_.insert(names_.end(), covariates.begin(), covariates.end());
    for (const TermParameterSpec& p : parameters) names_.push_back(p.name);
    slots_.assign(names_.size(), 0.0);
    for (std::size_t i = 0; i < names_.size(); ++i) parser_.DefineVar(names_[i], &slots_[i]);
  }

  /// Sets the expression and collects the identifiers it uses that are not variables; @throw mu::ParserError for
  /// a syntax error.
  void compile(const std::string& expression, std::vector<std::string>* used, std::vector<std::string>* unknown) {
    unknown_ = Unknown();
    parser_.SetVarFactory(&BoundParser::collect, &unknown_);
    parser_.SetExpr(expression);
    const mu::varmap_type vars = parser_.GetUsedVar();
    for (const auto& kv : vars)
      if (std::find(unknown_.names.begin(), unknown_.names.end(), kv.first) == unknown_.names.end())
        used->push_back(kv.first);
    *unknown = unknown_.names;
  }

  const std::vector<std::string>& names() const { return names_; }
  double* slot(std::size_t i) { return &slots_[i]; }
  double eval() { return parser_.Eval(); }

 private:
  struct Unknown {
    std::vector<std::string> names;
    std::deque<double> slots;
  };
  static double* collect(const char* name, void* user) {
    Unknown* u = static_cast<Unknown*>(user);
    u->names.push_back(name);
    u->slots.push_back(0.0);
    return &u->slots.back();
  }

  std::vector<std::string> names_;
  std::vector<double> slots_;  ///< sized once: DefineVar holds pointers into it
  Unknown unknown_;            ///< the factory's, as long as the parser may call it
  mu::Parser parser_;
};

/// Values of a data variable (operating variable or recorded covariate) on every run; false if the data lack it.
bool dataColumn(const std::string& name, const DiagnosisData& data, std::vector<double>* values) {
  values->clear();
  for (const OperatingVariable& v : operatingTable())
    if (name == v.name) {
      for (const DiagnosisRun& r : data.runs) values->push_back(v.value(r));
      return true;
    }
  for (const Covariate& c : data.covariates)
    if (c.name == name && !c.categorical) {
      *values = c.values;
      return true;
    }
  return false;
}

}  // namespace

const std::vector<std::string>& operatingVariables() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const OperatingVariable& v : operatingTable()) n.push_back(v.name);
    return n;
  }();
  return names;
}

std::vector<TermInfo> compileMechanisms(const MechanismFile& file) {
  auto fail = [&](int line, const std::string& what) {
    throw MechanismFileError(file.path + ":" + std::to_string(line) + ": " + what);
  };
  // Names taken by the library, the base levels, the outputs and the operating variables.
  std::set<std::string> builtin_terms,
      taken = {"w3_scale", "mu_scale", kOutputVariable, kSideForceVariable, kWearVariable};
  for (const TermInfo& t : termLibrary()) {
    if (t.user) continue;
    builtin_terms.insert(t.name);
    for (const TermParameterSpec& p : t.parameters) taken.insert(p.name);
  }
  for (const std::string& v : operatingVariables()) taken.insert(v);
  std::vector<TermInfo> terms;
  for (const MechanismSpec& spec : file.mechanisms) {
    const std::string what = "mechanism '" + spec.name + "': ";
    if (builtin_terms.count(spec.name))
      fail(spec.name_line, what + "the name is a built-in term (tread_wear_conceal --list); choose another");
    TermInfo info;
    info.term = Term::kNone;
    info.name = spec.name;
    info.statement = spec.statement;
    info.physical = spec.physical;
    info.affects[0] = info.affects[1] = false;
    for (std::size_t i = 0; i < spec.affects.size(); ++i) {
      const std::string& a = spec.affects[i];
      const int o = a == outputName(Output::kSideForce) ? 0 : a == outputName(Output::kWear) ? 1 : -1;
      if (o < 0) fail(spec.affects_lines[i], what + "affects: unknown output '" + a + "' (outputs: side_force, wear)");
      if (info.affects[o]) fail(spec.affects_lines[i], what + "affects: '" + a + "' is listed twice");
      info.affects[o] = true;
    }
    std::set<std::string> own;
    for (std::size_t i = 0; i < spec.covariates.size(); ++i) {
      const std::string& c = spec.covariates[i];
      if (taken.count(c) || !own.insert(c).second)
        fail(spec.covariates_lines[i],
             what + "covariate '" + c +
                 "' is taken (an operating variable, an output, a parameter) or listed twice: choose another");
    }
    for (const MechanismParameterSpec& p : spec.parameters) {
      if (taken.count(p.name) || own.count(p.name))
        fail(p.line, what + "parameter name '" + p.name +
                         "' is taken (by the library, another mechanism, an output, an operating variable or a "
                         "covariate): parameters are looked up by name, choose another");
      const double initial = std::isnan(p.initial) ? p.no_effect : p.initial;
      info.parameters.push_back({p.name, initial, p.lower, p.upper, false, p.no_effect, p.unit});
    }
    info.primary = 0;
    auto user = std::make_shared<UserMechanism>();
    user->file = file.path;
    user->line = spec.line;
    user->expression_line = spec.expression_line;
    user->expression = spec.expression;
    user->covariates = spec.covariates;
    user->test_magnitudes = spec.test_magnitudes;
    BoundParser parser(spec.covariates, info.parameters);
    std::vector<std::string> used, unknown;
    try {
      parser.compile(spec.expression, &used, &unknown);
    } catch (const mu::Parser::exception_type& e) {
      fail(spec.expression_line, what + "expression: " + e.GetMsg());
    }
    if (!unknown.empty()) {
      fail(spec.expression_line, what + "expression: unknown variable" + (unknown.size() > 1 ? "s " : " ") +
                                     joined(unknown) + " (valid: " + joined(parser.names()) +
                                     "; a recorded run-table column must be listed under covariates)");
    }
    for (const std::string& u : used) {
      const bool data_variable =
          std::find(operatingVariables().begin(), operatingVariables().end(), u) != operatingVariables().end() ||
          std::find(spec.covariates.begin(), spec.covariates.end(), u) != spec.covariates.end();
      if (data_variable) user->data_variables.push_back(u);
    }
    info.user = user;
    for (const TermParameterSpec& p : info.parameters) taken.insert(p.name);
    terms.push_back(std::move(info));
  }
  return terms;
}

MechanismsInUse::MechanismsInUse(const std::string& path) {
  if (path.empty()) return;
  previous_ = setUserTerms(compileMechanisms(readMechanismFile(path)));
  installed_ = true;
}

MechanismsInUse::~MechanismsInUse() {
  if (installed_) setUserTerms(std::move(previous_));
}

bool userMechanismApplicable(const TermInfo& info, const DiagnosisData& data, std::string* why_not) {
  auto no = [&](const std::string& why) {
    if (why_not) *why_not = why;
    return false;
  };
  if (!info.user) return no("not a user-defined mechanism");
  std::vector<double> values;
  for (const std::string& v : info.user->data_variables) {
    if (!dataColumn(v, data, &values)) return no("no numeric column '" + v + "' in the recordings");
    if (!std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); }))
      return no("'" + v + "' is not known for every run");
  }
  bool measured = false;
  for (int o = 0; o < kNumOutputs; ++o) measured = measured || (info.affects[o] && data.measured_count[o] > 0);
  return measured ? true : no("none of the outputs it affects is measured");
}

struct MechanismEvaluator::Impl {
  Impl(const TermInfo& info) : parser(info.user->covariates, info.parameters) {}
  BoundParser parser;
  std::vector<std::vector<double>> columns;  ///< per data variable the expression reads: its value per run
  std::vector<double*> column_slots;         ///< where each goes
  std::size_t first_parameter = 0;           ///< slot of the first parameter
  std::size_t num_parameters = 0;
  bool affects[kNumOutputs] = {false, false};
};

MechanismEvaluator::MechanismEvaluator(const TermInfo& info, const DiagnosisData& data) {
  if (!info.user) throw std::invalid_argument("'" + info.name + "' is not a user-defined mechanism");
  impl_ = std::make_unique<Impl>(info);
  std::vector<std::string> used, unknown;
  impl_->parser.compile(info.user->expression, &used, &unknown);  // compiled cleanly before (compileMechanisms)
  const std::vector<std::string>& names = impl_->parser.names();
  for (const std::string& v : info.user->data_variables) {
    std::vector<double> values;
    if (!dataColumn(v, data, &values))
      throw std::invalid_argument(info.user->where() + ": '" + info.name + "' reads '" + v + "', which the data lack");
    impl_->columns.push_back(std::move(values));
    impl_->column_slots.push_back(impl_->parser.slot(std::find(names.begin(), names.end(), v) - names.begin()));
  }
  impl_->num_parameters = info.parameters.size();
  impl_->first_parameter = names.size() - impl_->num_parameters;
  for (int o = 0; o < kNumOutputs; ++o) impl_->affects[o] = info.affects[o];
}

MechanismEvaluator::~MechanismEvaluator() = default;

void MechanismEvaluator::apply(int run, const double* parameters, double* side_force_n, double* wear_kg_per_m) {
  Impl& m = *impl_;
  for (std::size_t c = 0; c < m.columns.size(); ++c) *m.column_slots[c] = m.columns[c][run];
  for (std::size_t k = 0; k < m.num_parameters; ++k) *m.parser.slot(m.first_parameter + k) = parameters[k];
  *m.parser.slot(1) = *side_force_n;
  *m.parser.slot(2) = *wear_kg_per_m;
  double* outputs[kNumOutputs] = {side_force_n, wear_kg_per_m};
  double modified[kNumOutputs] = {*side_force_n, *wear_kg_per_m};
  for (int o = 0; o < kNumOutputs; ++o) {
    if (!m.affects[o]) continue;
    *m.parser.slot(0) = *outputs[o];
    try {
      modified[o] = m.parser.eval();
    } catch (const mu::Parser::exception_type&) {
      modified[o] = NAN;
    }
  }
  *side_force_n = modified[0];
  *wear_kg_per_m = modified[1];
}

void checkNoEffect(const TermInfo& info, const DiagnosisData& data, const Prediction& model) {
  MechanismEvaluator evaluator(info, data);
  std::vector<double> neutral;
  for (const TermParameterSpec& p : info.parameters) neutral.push_back(p.neutral);
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    double out[kNumOutputs] = {model.side_force_n[i], model.wear_kg_per_m[i]};
    evaluator.apply(static_cast<int>(i), neutral.data(), &out[0], &out[1]);
    for (int o = 0; o < kNumOutputs; ++o) {
      const double was = model.value(static_cast<Output>(o), static_cast<int>(i));
      if (std::isfinite(out[o]) && std::abs(out[o] - was) <= kNoEffectTolerance * std::abs(was)) continue;
      std::ostringstream s;
      s.precision(6);
      s << info.user->file << ":" << info.user->expression_line << ": mechanism '" << info.name
        << "': at its no-effect values the expression gives " << outputName(static_cast<Output>(o)) << " = " << out[o]
        << " on run " << i + 1 << " where the model gives " << was
        << (std::isfinite(out[o]) ? ": it must reduce to the model (`output`) there" : ": it must be finite there");
      throw DiagnosisError(s.str());
    }
  }
}

}  // namespace diagnosis
}  // namespace tread_wear
