#include "tread_wear/diagnosis/empirical.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "tread_wear/diagnosis/diagnosis.h"
#include "tread_wear/diagnosis/user_mechanisms.h"

namespace tread_wear {
namespace diagnosis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Largest relative change of the output over the recorded range allowed to the linear term (the factor stays in
/// [0.1, 1.9]); the quadratic splits it between its two parameters.
constexpr double kMaxLinearChange = 0.9;
/// Largest factor of the log-linear term over the recorded range (e^{+-ln 10}).
constexpr double kMaxLogChange = 2.302585092994046;
/// Saturating step: amplitude bounds [-] and time constant bounds as fractions of the covariate's range.
constexpr double kStepAmplitudeLower = -0.9, kStepAmplitudeUpper = 2.0;
constexpr double kStepTauLower = 0.05, kStepTauUpper = 2.0, kStepTauInitial = 0.25;
/// Permutations of the restricted diagnosis's locating tests (their results are not used; the minimum allowed).
constexpr int kInnerPermutations = 99;
/// Located covariates whose families are tried, in order of their locating p-value, until one term is accepted.
constexpr int kMaxCovariates = 3;

std::string exact(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

std::string brief(double v, int precision = 3) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

std::string percent(double v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << 100.0 * v << "%";
  return s.str();
}

/// Unit of a covariate from its name's suffix (the package's naming rule), "unit" when unknown.
std::string covariateUnit(const std::string& name) {
  if (name == "run_order") return "run";
  if (name == "slip_ratio") return "-";
  static const std::vector<std::pair<std::string, std::string>> suffixes = {
      {"_percent", "%"}, {"_per_m", "1/m"}, {"_mps", "m/s"}, {"_rad", "rad"}, {"_deg", "deg"},
      {"_kg", "kg"},     {"_c", "degC"},    {"_n", "N"},     {"_m", "m"},     {"_s", "s"}};
  for (const auto& [suffix, unit] : suffixes)
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      return unit;
  return "unit";
}

std::string perUnit(const std::string& unit, int power) {
  if (unit == "-") return "-";
  return "1/" + unit + (power > 1 ? "^" + std::to_string(power) : "");
}

/// One generated term: a user mechanism reading `covariate`.
TermInfo makeTerm(const std::string& name, const std::string& statement, Output output, const std::string& covariate,
                  bool operating_variable, const std::string& expression, std::vector<TermParameterSpec> parameters) {
  TermInfo info;
  info.term = Term::kNone;
  info.name = name;
  info.statement = statement;
  info.physical = false;
  info.affects[0] = output == Output::kSideForce;
  info.affects[1] = output == Output::kWear;
  info.parameters = std::move(parameters);
  info.primary = 0;
  auto user = std::make_shared<UserMechanism>();
  user->file = "empirical";
  user->expression = expression;
  if (!operating_variable) user->covariates = {covariate};
  user->data_variables = {covariate};
  info.user = user;
  return info;
}

/// Group offsets in a numbered categorical covariate (cycle_id): output (1 + d_g [x == g]) for every group g but
/// the first, whose level the model's w3_scale carries.
std::vector<TermInfo> groupOffsets(const DiagnosisData& data, const Covariate& c, Output output, std::string* why_not) {
  std::vector<double> numbers;
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    const double x = data.runs[i].cycle >= 0 ? data.runs[i].cycle : kNaN;
    if (!std::isfinite(x)) {
      if (why_not) *why_not = "'" + c.name + "': not known for every run";
      return {};
    }
    if (std::find(numbers.begin(), numbers.end(), x) == numbers.end()) numbers.push_back(x);
  }
  std::sort(numbers.begin(), numbers.end());
  if (numbers.size() < 2) {
    if (why_not) *why_not = "'" + c.name + "': no variance on the runs (one group): no offsets to fit";
    return {};
  }
  std::string expression = "output * (1";
  std::vector<TermParameterSpec> parameters;
  for (std::size_t g = 1; g < numbers.size(); ++g) {
    const std::string name = "emp_grp_d" + exact(numbers[g]);
    expression += " + " + name + " * (" + c.name + " == " + exact(numbers[g]) + ")";
    parameters.push_back({name, 0.0, kStepAmplitudeLower, kStepAmplitudeUpper, false, 0.0, "-"});
  }
  expression += ")";
  return {makeTerm("empirical_group_offsets_" + c.name,
                   "empirical, not physics: " + std::string(outputName(output)) + " offset per " + c.name, output,
                   c.name, true, expression, std::move(parameters))};
}

}  // namespace

std::vector<TermInfo> empiricalFamily(const DiagnosisData& data, const std::string& covariate, Output output,
                                      std::string* why_not) {
  auto none = [&](const std::string& why) {
    if (why_not) *why_not = "'" + covariate + "': " + why;
    return std::vector<TermInfo>{};
  };
  const auto c = std::find_if(data.covariates.begin(), data.covariates.end(),
                              [&](const Covariate& v) { return v.name == covariate; });
  if (c == data.covariates.end())
    return none("not a covariate of the recordings (a column without variance is not one, data.h)");
  const std::vector<std::string>& operating = operatingVariables();
  const bool operating_variable = std::find(operating.begin(), operating.end(), covariate) != operating.end();
  if (c->categorical) {
    if (!operating_variable)
      return none(
          "categorical and not numbered: group offsets need the group's number in an expression (only "
          "cycle_id has one)");
    return groupOffsets(data, *c, output, why_not);
  }
  if (!operating_variable && c->kind != "recorded")
    return none("derived (" + c->kind + "), not a variable an expression can read");
  double sum = 0.0, lo = kNaN, hi = kNaN;
  for (double x : c->values) {
    if (!std::isfinite(x)) return none("not known for every run");
    sum += x;
    lo = std::isnan(lo) ? x : std::min(lo, x);
    hi = std::isnan(hi) ? x : std::max(hi, x);
  }
  if (c->values.empty() || !(hi > lo))
    return none("no variance on the runs (every value " + (c->values.empty() ? "missing" : exact(lo)) +
                "): an empirical term in it cannot be told from the model's level");
  const double m = sum / static_cast<double>(c->values.size());
  const double d = std::max(hi - m, m - lo);
  const std::string unit = covariateUnit(covariate);
  const std::string dx = "(" + covariate + " - " + exact(m) + ")";
  const std::string out = outputName(output);
  const std::string what = "empirical, not physics: " + out + " ";
  std::vector<TermInfo> family;
  const std::string lin = "emp_lin_b";
  family.push_back(makeTerm("empirical_linear_" + covariate, what + "linear in " + covariate, output, covariate,
                            operating_variable, "output * (1 + " + lin + " * " + dx + ")",
                            {{lin, 0.0, -kMaxLinearChange / d, kMaxLinearChange / d, false, 0.0, perUnit(unit, 1)}}));
  const std::string q1 = "emp_quad_b1", q2 = "emp_quad_b2";
  const double half = 0.5 * kMaxLinearChange;
  family.push_back(makeTerm("empirical_quadratic_" + covariate, what + "quadratic in " + covariate, output, covariate,
                            operating_variable, "output * (1 + " + q1 + " * " + dx + " + " + q2 + " * " + dx + "^2)",
                            {{q1, 0.0, -half / d, half / d, false, 0.0, perUnit(unit, 1)},
                             {q2, 0.0, -half / (d * d), half / (d * d), false, 0.0, perUnit(unit, 2)}}));
  const std::string lg = "emp_log_b";
  family.push_back(makeTerm("empirical_log_linear_" + covariate, what + "log-linear in " + covariate, output, covariate,
                            operating_variable, "output * exp(" + lg + " * " + dx + ")",
                            {{lg, 0.0, -kMaxLogChange / d, kMaxLogChange / d, false, 0.0, perUnit(unit, 1)}}));
  if (c->kind == "sequence") {
    const std::string a = "emp_step_a", tau = "emp_step_tau";
    const double range = hi - lo;
    family.push_back(
        makeTerm("empirical_saturating_step_" + covariate, what + "saturating step in " + covariate, output, covariate,
                 operating_variable,
                 "output * (1 + " + a + " * (1 - exp(-(" + covariate + " - " + exact(lo) + ") / " + tau + ")))",
                 {{a, 0.0, kStepAmplitudeLower, kStepAmplitudeUpper, false, 0.0, "-"},
                  // tau's no-effect value is any: a = 0 leaves the model whatever tau is
                  {tau, kStepTauInitial * range, kStepTauLower * range, kStepTauUpper * range, true,
                   kStepTauInitial * range, unit}}));
  }
  return family;
}

namespace {

/// The restricted selection over one covariate's family: true and *term filled when one is accepted, else *why.
bool selectFromFamily(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options,
                      std::vector<TermInfo> family, const std::string& covariate, Output output, EmpiricalTerm* term,
                      std::vector<std::string>* log, std::string* why) {
  // The family joins this thread's library for the restricted diagnosis only.
  std::vector<TermInfo> library = termLibrary();
  DiagnosisOptions restricted = options;
  restricted.candidates.clear();
  for (TermInfo& t : family) {
    t.term = static_cast<Term>(library.size());
    restricted.candidates.push_back(t.term);
    library.push_back(t);
  }
  restricted.max_terms = 1;
  restricted.detection_power = 0.0;
  restricted.permutations = kInnerPermutations;
  restricted.empirical = false;
  struct Restore {
    const std::vector<TermInfo>* previous;
    ~Restore() { setThreadLibrary(previous); }
  } restore{setThreadLibrary(&library)};
  const DiagnosisResult r = diagnose(base, data, restricted);
  for (const std::string& l : r.log) log->push_back("'" + covariate + "' (" + data.cv_scheme + "): " + l);
  const int o = static_cast<int>(output);
  if (r.final_model.terms.empty()) {
    *why = "no empirical term in '" + covariate + "' improved the held-out error significantly";
    return false;
  }
  const TermInfo& info = termInfo(r.final_model.terms.front());
  // The selection's statistics: the accepted fit under the base model's weights, beside the base model.
  const auto selected = std::find_if(r.tried.begin(), r.tried.end(),
                                     [&](const FittedModel& f) { return f.label == r.final_model.label && f.cv_done; });
  const FittedModel& fit = selected != r.tried.end() ? *selected : r.final_model;
  term->name = info.name;
  term->form = info.name.substr(std::string("empirical_").size(),
                                info.name.size() - std::string("empirical_").size() - covariate.size() - 1);
  term->covariate = covariate;
  term->output = output;
  term->expression = info.user->expression;
  term->cv_scheme = data.cv_scheme;
  for (const Covariate& c : data.covariates)
    if (c.name == covariate && !c.categorical) {
      double sum = 0.0;
      for (double x : c.values) sum += x;
      term->centre = sum / static_cast<double>(c.values.size());
    }
  for (const TermParameterSpec& p : info.parameters) {
    EmpiricalParameter ep;
    ep.name = p.name;
    ep.value = fittedValue(r.final_model, p.name, &ep.std_error);
    ep.unit = p.unit;
    term->parameters.push_back(ep);
  }
  for (std::size_t i = 0; i < data.runs.size(); ++i)
    term->prediction.push_back(r.final_model.prediction.value(output, static_cast<int>(i)));
  term->rmser_before = r.base.rmser[o];
  term->cv_rmser_before = r.base.cv_rmser[o];
  term->rmser_after = fit.rmser[o];
  term->cv_rmser_after = fit.cv_rmser[o];
  term->p_value = fit.p_vs_parent;
  term->delta_aicc = r.base.aicc - fit.aicc;
  return true;
}

}  // namespace

EmpiricalResult fitEmpiricalTerms(const TireParams& base, const DiagnosisData& data, const DiagnosisOptions& options,
                                  const DiagnosisResult& result) {
  EmpiricalResult out;
  if (result.explanation != "unexplained") return out;
  out.attempted = true;
  std::vector<std::string> reasons;
  // Covariates first, group offsets last: an offset per group cannot predict a group held out whole, while a
  // covariate constant within each group (humidity per cycle) can, and is judged by the data's scheme, which holds
  // out whole groups. The offsets come only when no covariate's term is accepted, as a description of the groups.
  for (const bool categorical_pass : {false, true}) {
    for (const LocatedEffect& e : result.located_before) {  // sorted by p
      if (e.categorical != categorical_pass) continue;
      if (!e.significant || static_cast<int>(out.covariates.size()) >= kMaxCovariates) continue;
      if (std::find(out.covariates.begin(), out.covariates.end(), e.covariate) != out.covariates.end()) continue;
      std::string why;
      const std::vector<TermInfo> family = empiricalFamily(data, e.covariate, e.output, &why);
      if (family.empty()) {
        reasons.push_back(why);
        continue;
      }
      out.covariates.push_back(e.covariate);
      for (const TermInfo& t : family) out.family.push_back(t.name);
      EmpiricalTerm term;
      bool accepted = false;
      if (e.categorical) {
        // A batch offset cannot predict a group held out whole: its held-out error is leave one run out, and the
        // term describes the recorded groups only (empiricalSummary says so).
        DiagnosisData per_run = data;
        for (std::size_t i = 0; i < per_run.cv_groups.size(); ++i) per_run.cv_groups[i] = std::to_string(i);
        per_run.cv_scheme = "leave one run out";
        per_run.cv_calibration_run.clear();
        accepted = selectFromFamily(base, per_run, options, family, e.covariate, e.output, &term, &out.log, &why);
      } else {
        accepted = selectFromFamily(base, data, options, family, e.covariate, e.output, &term, &out.log, &why);
      }
      if (accepted) {
        out.covariate = e.covariate;
        out.output = e.output;
        out.terms.push_back(term);
        return out;
      }
      reasons.push_back(why);
    }
  }
  if (out.covariates.empty()) reasons.insert(reasons.begin(), "no located covariate an empirical term can be built in");
  for (const std::string& r : reasons) out.reason += (out.reason.empty() ? "" : "; ") + r;
  return out;
}

std::string empiricalSummary(const EmpiricalTerm& t) {
  std::ostringstream s;
  const std::string out = outputName(t.output);
  const std::string dx = "(" + t.covariate + " - " + brief(t.centre, 4) + ")";
  if (t.form == "linear")
    s << out << " x (1 + b " << dx << ")";
  else if (t.form == "quadratic")
    s << out << " x (1 + b1 " << dx << " + b2 " << dx << "^2)";
  else if (t.form == "log_linear")
    s << out << " x exp(b " << dx << ")";
  else if (t.form == "group_offsets")
    s << out << " x (1 + d_g) in group g of " << t.covariate << " (d = 0 in the first)";
  else
    s << out << " x (1 + a (1 - exp(-(" << t.covariate << " - min) / tau)))";
  const char* symbols_linear[] = {"b"};
  const char* symbols_quadratic[] = {"b1", "b2"};
  const char* symbols_step[] = {"a", "tau"};
  const char* const* symbols = t.form == "quadratic"         ? symbols_quadratic
                               : t.form == "saturating_step" ? symbols_step
                                                             : symbols_linear;
  for (std::size_t i = 0; i < t.parameters.size(); ++i) {
    const EmpiricalParameter& p = t.parameters[i];
    const std::string symbol =
        t.form == "group_offsets" ? "d_" + p.name.substr(std::string("emp_grp_d").size()) : std::string(symbols[i]);
    s << ", " << symbol << " = " << brief(p.value) << " +- " << brief(p.std_error, 2)
      << (p.unit == "-" ? "" : " " + p.unit);
  }
  s << ", held-out " << out << " RMSER " << percent(t.cv_rmser_before) << " -> " << percent(t.cv_rmser_after) << " ("
    << t.cv_scheme << ")";
  if (t.form == "group_offsets") s << "; describes the recorded groups only: it cannot predict a group not seen";
  return s.str();
}

}  // namespace diagnosis
}  // namespace tread_wear
