#include "tread_wear/proving/harness.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "tread_wear/diagnosis/statistics.h"
#include "tread_wear/diagnosis/user_mechanisms.h"

namespace tread_wear {
namespace diagnosis {
namespace {

/// Parameter criterion of the issue: within 25% of the true effect.
constexpr double kParameterTolerance = 0.25;

/// Small and large magnitudes of each term's primary parameter in the harness.
std::vector<std::pair<std::string, double>> magnitudes(Term t, bool two) {
  if (t == Term::kNone) {  // rough_road (the only effect that is no term): beta
    if (!two) return {{"default", kRoughRoadDefaultBeta}};
    return {{"small", 0.35}, {"large", 0.7}};
  }
  double small = 0.0, large = 0.0;
  if (!two || t == Term::kTurnSlipOrientation || !smallAndLargeMagnitudes(t, &small, &large))
    return {{"default", defaultMagnitude(t)}};
  return {{"small", small}, {"large", large}};
}

std::string pct(int num, int den) {
  if (den == 0) return "-";
  std::ostringstream s;
  // One decimal, so that a rate just under a target (e.g. 122/136 = 89.7%) does not print as the target.
  s << std::fixed << std::setprecision(num == den || num == 0 ? 0 : 1) << 100.0 * num / den << "% (" << num << "/"
    << den << ")";
  return s.str();
}

/// pct with the 95% Wilson interval: how far a rate measured on this many cases can be from the true rate.
std::string pctWithInterval(int num, int den) {
  if (den == 0) return "-";
  const ProportionInterval ci = wilsonInterval(num, den);
  std::ostringstream s;
  s << pct(num, den) << " [95% CI " << std::fixed << std::setprecision(1) << 100.0 * ci.lower << "-" << 100.0 * ci.upper
    << "%]";
  return s.str();
}

/// The size of the hidden effect against which a parameter estimate is scored: |truth - neutral|, or |truth|
/// without a neutral value (thermal_wear's sigma_T).
double effectSize(const ConcealAnswer& answer) {
  return std::isfinite(answer.primary_neutral) ? std::abs(answer.primary_value - answer.primary_neutral)
                                               : std::abs(answer.primary_value);
}

/// Probability under the detectability reference that the case is right and its parameter within the tolerance.
double referenceParameterOk(const ConcealAnswer& answer, const Detectability& reference) {
  for (const ReferenceParameter& p : reference.parameters)
    if (p.name == answer.primary && p.std_error > 0.0) {
      const double within = std::erf(kParameterTolerance * effectSize(answer) / (p.std_error * std::sqrt(2.0)));
      return reference.expected_right * within;
    }
  return std::numeric_limits<double>::quiet_NaN();
}

/// The detectability columns of a CSV line: lambda, power, expected right, parameter, and the oracle's most likely
/// wrong verdict with its share (empty without a reference).
std::string referenceCsv(const HarnessOutcome& o) {
  if (!o.information) return ",,,,,";
  const Detectability& d = o.reference;
  std::ostringstream s;
  s << std::setprecision(6) << d.lambda << "," << d.power << "," << d.expected_right << "," << o.reference_parameter_ok
    << ",";
  const auto wrong =
      std::find_if(d.verdicts.begin(), d.verdicts.end(), [&](const OracleVerdict& v) { return v.verdict != d.hidden; });
  if (wrong != d.verdicts.end())
    s << wrong->verdict << "," << wrong->probability;
  else
    s << ",";
  return s.str();
}

/// Scores a rough_road case (harness.h): o has the verdict and the held-out errors of the base model.
HarnessOutcome scoreRoughRoad(HarnessOutcome o, const ConcealAnswer& answer, const DiagnosisResult& result) {
  o.sensor_scored = true;  // a road effect on the wear leaves the (unmeasured) side force alone
  for (Term s : result.final_model.terms) o.false_sensor = o.false_sensor || !termInfo(s).physical;
  o.empirical_scored = o.improved_scored = o.parameter_scored = true;
  o.truth = answer.primary_value;
  const int wear = static_cast<int>(Output::kWear);
  for (const EmpiricalTerm& e : result.empirical.terms) {
    o.empirical_covariate = e.covariate;
    o.empirical_ok =
        e.covariate == "rough_road_share" && e.output == Output::kWear && e.cv_rmser_after < e.cv_rmser_before;
    o.cv_after[wear] = e.cv_rmser_after;
    if (o.empirical_ok && e.form == "linear" && !e.parameters.empty()) {
      o.parameter_estimated = true;
      o.estimate = e.parameters.front().value;
      o.std_error = e.parameters.front().std_error;
      o.parameter_covered = std::isfinite(o.std_error) && std::abs(o.estimate - o.truth) <= 2.0 * o.std_error;
      o.parameter_ok = std::abs(o.estimate - o.truth) <= kParameterTolerance * effectSize(answer);
      o.parameter_ok_relative = std::abs(o.estimate - o.truth) <= kParameterTolerance * std::abs(o.truth);
    }
  }
  o.right = o.empirical_ok;
  o.improved = o.cv_after[wear] < o.cv_before[wear];
  o.all_met = o.right && o.parameter_ok && o.improved;
  return o;
}

}  // namespace

std::vector<HarnessCase> harnessCases(const HarnessOptions& options) {
  std::vector<HarnessCase> cases;
  std::vector<std::string> effects = options.effects;
  const bool drives = options.design == "drives";
  if (effects.empty() && drives) effects = {termInfo(Term::kThermalWear).name, kRoughRoadEffect};
  if (effects.empty())
    for (const TermInfo& t : termLibrary())  // the road wear terms apply to drive segments only (extensions.h)
      if (t.term != Term::kContactTimeWear && t.term != Term::kAdhesionWear) effects.push_back(t.name);
  std::uint64_t seed = options.seed;
  for (double wn : options.wear_noise) {
    const double fn = options.side_force_noise_n * wn / 0.05;
    for (const std::string& e : effects) {
      Term t = Term::kNone;
      if (!(drives && e == kRoughRoadEffect) && !parseTerm(e, &t)) continue;
      if (t != Term::kNone && termInfo(t).primary >= 0 && std::isnan(defaultMagnitude(t)))
        throw std::invalid_argument("effect '" + e + "' has no magnitudes for generated cases (test_magnitudes in " +
                                    "its mechanisms file)");
      for (const auto& [label, mag] : magnitudes(t, options.two_magnitudes))
        for (int r = 0; r < options.repeats; ++r) {
          HarnessCase c;
          c.spec.effect = e;
          c.spec.magnitude = mag;
          c.spec.design = options.design;
          c.spec.fleet = options.fleet;
          c.spec.wear_noise_rsd = wn;
          c.spec.side_force_noise_n = fn;
          c.spec.seed = ++seed;
          c.spec.model = {options.generator_preset, options.diagnosis.model.orientation};
          c.magnitude_label = label;
          c.out_of_library = options.out_of_library;
          cases.push_back(c);
        }
    }
    for (int r = 0; r < options.control_repeats; ++r) {
      HarnessCase c;
      c.spec.effect = "none";
      c.spec.design = options.design;
      c.spec.fleet = options.fleet;
      c.spec.wear_noise_rsd = wn;
      c.spec.side_force_noise_n = fn;
      c.spec.seed = ++seed;
      c.spec.model = {options.generator_preset, options.diagnosis.model.orientation};
      c.magnitude_label = "-";
      c.out_of_library = options.out_of_library;
      cases.push_back(c);
    }
  }
  return cases;
}

HarnessOutcome scoreCase(const HarnessCase& c, const ConcealAnswer& answer, const DiagnosisResult& result) {
  HarnessOutcome o;
  o.c = c;
  o.explanation = result.explanation;
  o.right = result.explanation == answer.effect;
  o.named = o.right || std::any_of(result.close_alternatives.begin(), result.close_alternatives.end(),
                                   [&](const CloseAlternative& a) { return a.model == answer.effect; });
  o.preset = presetName(result.preset);
  for (int k = 0; k < kNumOutputs; ++k) {
    o.cv_before[k] = result.base.cv_rmser[k];
    o.cv_after[k] = result.final_model.cv_rmser[k];
  }
  if (answer.effect == kRoughRoadEffect) return scoreRoughRoad(o, answer, result);
  Term t = Term::kNone;
  const bool has_effect = answer.effect != "none";
  if (has_effect) parseTerm(answer.effect, &t);
  o.sensor_scored = !has_effect || !termInfo(t).affects[static_cast<int>(Output::kSideForce)];
  if (o.sensor_scored)
    for (Term s : result.final_model.terms) o.false_sensor = o.false_sensor || !termInfo(s).physical;
  if (!has_effect) return o;
  const TermInfo& info = termInfo(t);
  if (c.out_of_library && info.user) {
    o.empirical_scored = true;
    for (const EmpiricalTerm& e : result.empirical.terms) {
      o.empirical_covariate = e.covariate;
      const std::vector<std::string>& reads = info.user->data_variables;
      o.empirical_ok = std::find(reads.begin(), reads.end(), e.covariate) != reads.end() &&
                       info.affects[static_cast<int>(e.output)] && e.cv_rmser_after < e.cv_rmser_before;
    }
  }
  o.improved_scored = true;
  o.improved = true;
  for (int k = 0; k < kNumOutputs; ++k)
    if (info.affects[k]) o.improved = o.improved && o.cv_after[k] < o.cv_before[k];
  if (!answer.primary.empty()) {
    o.truth = answer.primary_value;
    const bool selected = std::find(result.final_model.terms.begin(), result.final_model.terms.end(), t) !=
                          result.final_model.terms.end();
    o.parameter_scored = true;
    if (selected) {
      o.parameter_estimated = true;
      o.estimate = fittedValue(result.final_model, answer.primary, &o.std_error);
      o.parameter_covered = std::isfinite(o.std_error) && std::abs(o.estimate - o.truth) <= 2.0 * o.std_error;
      const double scale = effectSize(answer);
      o.parameter_ok = std::abs(o.estimate - o.truth) <= kParameterTolerance * scale;
      o.parameter_ok_relative = std::abs(o.estimate - o.truth) <= kParameterTolerance * std::abs(o.truth);
    }
  }
  o.all_met = o.right && (!o.parameter_scored || o.parameter_ok) && o.improved;
  return o;
}

std::vector<HarnessOutcome> runHarness(const TireParams& base, const HarnessOptions& options, std::ostream* progress) {
  const std::vector<HarnessCase> cases = harnessCases(options);
  std::vector<HarnessOutcome> outcomes(cases.size());
  std::atomic<std::size_t> next{0};
  std::mutex io;
  auto worker = [&]() {
    for (std::size_t i = next++; i < cases.size(); i = next++) {
      const auto t0 = std::chrono::steady_clock::now();
      HarnessOutcome o;
      try {
        const ConcealCase cc = concealEffect(base, cases[i].spec);
        const DiagnosisData data = buildDiagnosisData(cc.table);
        DiagnosisOptions dopt = options.diagnosis;
        dopt.seed = cases[i].spec.seed;
        dopt.detection_power = 0.0;  // the harness scores verdicts; the reference below is its power calculation
        if (cases[i].out_of_library && dopt.candidates.empty())
          for (int t = 0; t < static_cast<int>(Term::kFirstUser); ++t)
            if (termInfo(static_cast<Term>(t)).name != cases[i].spec.effect)
              dopt.candidates.push_back(static_cast<Term>(t));
        const auto d0 = std::chrono::steady_clock::now();
        const DiagnosisResult r = diagnose(base, data, dopt);
        const double diagnosis_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - d0).count();
        o = scoreCase(cases[i], cc.answer, r);
        o.diagnosis_seconds = diagnosis_seconds;
        o.cells = ExtendedModel(base, dopt.model, {}, data).evaluationPoints();
        if (options.information && cases[i].spec.wear_noise_rsd > 0.0 && cases[i].spec.side_force_noise_n > 0.0) {
          const DetectabilityOptions d =
              detectabilityOptions(dopt, cases[i].spec.wear_noise_rsd, cases[i].spec.side_force_noise_n);
          try {  // the case's verdict stands even when its reference cannot be computed
            o.reference = detectability(base, buildDiagnosisData(cc.noise_free), cases[i].spec.effect, d);
            o.information = true;
            if (!cc.answer.primary.empty()) o.reference_parameter_ok = referenceParameterOk(cc.answer, o.reference);
          } catch (const std::exception& e) {
            o.reference_error = e.what();
          }
        }
      } catch (const std::exception& e) {
        o.c = cases[i];
        o.error = e.what();
      }
      o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      outcomes[i] = o;
      if (progress) {
        std::lock_guard<std::mutex> lock(io);
        *progress << "[" << i + 1 << "/" << cases.size() << "] " << o.c.spec.effect << " " << o.c.magnitude_label
                  << " noise " << o.c.spec.wear_noise_rsd << " seed " << o.c.spec.seed << " -> "
                  << (o.error.empty() ? o.explanation : "ERROR " + o.error)
                  << (o.empirical_scored ? " (empirical term in: " +
                                               (o.empirical_covariate.empty() ? "none" : o.empirical_covariate) + ")"
                                         : "")
                  << (o.reference_error.empty() ? "" : " (no reference: " + o.reference_error + ")") << " ("
                  << std::fixed << std::setprecision(1) << o.seconds << " s"
                  << (o.c.spec.design == "drives" ? ", " + std::to_string(o.cells) + " cells" : "") << ")\n"
                  << std::defaultfloat;
      }
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < std::max(1, options.jobs); ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  return outcomes;
}

namespace {

/// Counts over cases; `n` counts the cases that ran (failed ones only in `errors`).
struct Tally {
  int n = 0, right = 0, named = 0, sensor_scored = 0, false_sensor = 0, pscored = 0, pok = 0, pok_relative = 0,
      pestimated = 0, pcovered = 0, iscored = 0, iok = 0, all_met = 0, errors = 0, referenced = 0, reference_errors = 0,
      escored = 0, eok = 0;
  double expected_right = 0.0;  ///< sum of the cases' detectability references
  int parameter_referenced = 0;
  double expected_parameter = 0.0;  ///< sum of their reference_parameter_ok

  void add(const HarnessOutcome& o) {
    if (!o.error.empty()) {
      ++errors;
      return;
    }
    ++n;
    right += o.right;
    named += o.named;
    sensor_scored += o.sensor_scored;
    false_sensor += o.false_sensor;
    pscored += o.parameter_scored;
    pok += o.parameter_ok;
    pok_relative += o.parameter_ok_relative;
    all_met += o.all_met;
    pestimated += o.parameter_estimated;
    pcovered += o.parameter_covered;
    iscored += o.improved_scored;
    iok += o.improved;
    escored += o.empirical_scored;
    eok += o.empirical_ok;
    referenced += o.information;
    reference_errors += !o.reference_error.empty();
    if (o.information) expected_right += o.reference.expected_right;
    if (std::isfinite(o.reference_parameter_ok)) {
      ++parameter_referenced;
      expected_parameter += o.reference_parameter_ok;
    }
  }
  /// Mean detectability reference of the explanation and of the parameter in percent, "-" without one.
  std::string expected() const { return meanPercent(expected_right, referenced); }
  std::string expectedParameter() const { return meanPercent(expected_parameter, parameter_referenced); }
  static std::string meanPercent(double sum, int count) {
    if (count == 0) return "-";
    std::ostringstream s;
    s << std::fixed << std::setprecision(1) << 100.0 * sum / count << "%";
    return s.str();
  }
};

/// The totals of one wear-noise level: the hidden effects and the no-effect controls, with intervals.
std::string totalsParagraph(double noise, const Tally& effects, const Tally& controls, bool information) {
  std::ostringstream s;
  s << "\nAt wear RSD " << noise * 100 << "%: right explanation " << pctWithInterval(effects.right, effects.n)
    << ", parameter within 25% " << pctWithInterval(effects.pok, effects.pscored)
    << " (when selected, truth within 2 standard errors " << pctWithInterval(effects.pcovered, effects.pestimated)
    << "), held-out RMSER improved " << pctWithInterval(effects.iok, effects.iscored) << "; controls `none` "
    << pctWithInterval(controls.right, controls.n) << ". Parameter within 25% of its own value (|estimate - "
    << "truth| <= 0.25 |truth|) " << pctWithInterval(effects.pok_relative, effects.pscored)
    << "; right, parameter and improved in the same case " << pctWithInterval(effects.all_met, effects.n)
    << ". The hidden term named as the explanation or as a close alternative "
    << pctWithInterval(effects.named, effects.n) << ". A sensor term named where the hidden effect does not "
    << "touch the side force (controls, wear-only effects) "
    << pctWithInterval(effects.false_sensor + controls.false_sensor, effects.sensor_scored + controls.sensor_scored)
    << ".\n";
  if (effects.escored > 0)
    s << "Out of library (the library lacks the hidden mechanism): the right covariate with an empirical term that "
         "lowers the held-out RMSER "
      << pctWithInterval(effects.eok, effects.escored) << ".\n";
  if (information)
    s << "Detectability reference (a selector that knows the noise levels, detectability.h): expected right "
         "explanation "
      << effects.expected() << " of the hidden effects, parameter within 25% " << effects.expectedParameter()
      << ", `none` " << controls.expected() << " of the controls"
      << (effects.reference_errors + controls.reference_errors > 0
              ? "; " + std::to_string(effects.reference_errors + controls.reference_errors) +
                    " case(s) without a reference, see the progress log"
              : "")
      << ".\n";
  return s.str();
}

/// The drive cases' cells and diagnosis wall times (median, range); empty without drive cases.
std::string driveCasesLine(const std::vector<HarnessOutcome>& outcomes) {
  std::ostringstream s;
  std::vector<double> cells, diagnosis_s;
  for (const HarnessOutcome& o : outcomes)
    if (o.error.empty() && o.c.spec.design == "drives") {
      cells.push_back(static_cast<double>(o.cells));
      diagnosis_s.push_back(o.diagnosis_seconds);
    }
  if (!cells.empty()) {
    auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    };
    s << "\nDrive cases: " << std::fixed << std::setprecision(0) << *std::min_element(cells.begin(), cells.end()) << "-"
      << *std::max_element(cells.begin(), cells.end()) << " cells (median " << median(cells)
      << "), diagnosis wall time median " << std::setprecision(1) << median(diagnosis_s) << " s (max "
      << *std::max_element(diagnosis_s.begin(), diagnosis_s.end()) << " s) per case.\n";
  }
  return s.str();
}

}  // namespace

std::string harnessTable(const std::vector<HarnessOutcome>& outcomes) {
  const bool information =
      std::any_of(outcomes.begin(), outcomes.end(), [](const HarnessOutcome& o) { return o.information; });
  // A reference cell (or nothing, without references).
  auto referenceCell = [&](const std::string& value) { return information ? " " + value + " |" : std::string(); };
  const std::string reference_header = information ? " expected right (detectability reference) |" : "";
  const std::string parameter_reference_header = information ? " expected parameter within 25% (reference) |" : "";
  const std::string reference_rule = information ? "---|" : "";

  std::map<std::tuple<std::string, std::string, double>, Tally> rows;
  std::map<std::pair<std::string, double>, Tally> per_effect;
  // Totals per wear-noise level: the hidden effects (first) and the no-effect controls (second).
  std::map<double, std::pair<Tally, Tally>> totals;
  std::vector<std::string> order;
  for (const HarnessOutcome& o : outcomes) {
    rows[std::make_tuple(o.c.spec.effect, o.c.magnitude_label, o.c.spec.wear_noise_rsd)].add(o);
    per_effect[{o.c.spec.effect, o.c.spec.wear_noise_rsd}].add(o);
    auto& total = totals[o.c.spec.wear_noise_rsd];
    (o.c.spec.effect == "none" ? total.second : total.first).add(o);
    if (std::find(order.begin(), order.end(), o.c.spec.effect) == order.end()) order.push_back(o.c.spec.effect);
  }
  std::ostringstream s;
  s << "| hidden effect | magnitude | wear RSD | cases | right explanation |" << reference_header
    << " parameter within 25% |" << parameter_reference_header << " held-out RMSER improved |\n|---|---|---|---|---|"
    << reference_rule << "---|" << reference_rule << "---|\n";
  for (const std::string& e : order)
    for (const auto& [key, t] : rows) {
      if (std::get<0>(key) != e) continue;
      s << "| " << e << " | " << std::get<1>(key) << " | " << std::get<2>(key) * 100 << "% | " << t.n + t.errors
        << " | " << pct(t.right, t.n) << " |" << referenceCell(t.expected()) << " " << pct(t.pok, t.pscored) << " |"
        << referenceCell(t.expectedParameter()) << " " << pct(t.iok, t.iscored) << " |"
        << (t.errors ? " " + std::to_string(t.errors) + " failed" : "") << "\n";
    }
  s << "\nPer effect (all magnitudes):\n\n| hidden effect | wear RSD | cases | right explanation (`none` for "
       "controls) |"
    << reference_header << " parameter within 25% |" << parameter_reference_header
    << " truth within 2 standard errors (when selected) | held-out RMSER improved |\n|---|---|---|---|"
    << reference_rule << "---|" << reference_rule << "---|---|\n";
  for (const std::string& e : order)
    for (const auto& [key, t] : per_effect) {
      if (key.first != e) continue;
      s << "| " << e << " | " << key.second * 100 << "% | " << t.n + t.errors << " | " << pct(t.right, t.n) << " |"
        << referenceCell(t.expected()) << " " << pct(t.pok, t.pscored) << " |" << referenceCell(t.expectedParameter())
        << " " << pct(t.pcovered, t.pestimated) << " | " << pct(t.iok, t.iscored) << " |\n";
    }
  for (const auto& [noise, total] : totals) s << totalsParagraph(noise, total.first, total.second, information);
  s << driveCasesLine(outcomes);
  return s.str();
}

std::string harnessCsv(const std::vector<HarnessOutcome>& outcomes) {
  std::ostringstream s;
  s << std::setprecision(8);
  s << "effect,magnitude_label,magnitude,wear_noise_rsd,side_force_noise_n,seed,explanation,right,named,parameter_ok,"
       "parameter_ok_relative,all_met,estimate,truth,std_error,covered,improved,cv_before_side_force,cv_before_wear,"
       "cv_after_side_force,cv_after_wear,reference_lambda,reference_power,reference_expected_right,"
       "reference_parameter_ok,reference_top_wrong,reference_top_wrong_share,preset,false_sensor,seconds,error,"
       "empirical_covariate,empirical_ok,cells,diagnosis_seconds\n";
  for (const HarnessOutcome& o : outcomes)
    s << o.c.spec.effect << "," << o.c.magnitude_label << "," << o.c.spec.magnitude << "," << o.c.spec.wear_noise_rsd
      << "," << o.c.spec.side_force_noise_n << "," << o.c.spec.seed << "," << o.explanation << "," << o.right << ","
      << o.named << "," << (o.parameter_scored ? std::to_string(o.parameter_ok) : "") << ","
      << (o.parameter_scored ? std::to_string(o.parameter_ok_relative) : "") << ","
      << (o.c.spec.effect == "none" ? "" : std::to_string(o.all_met)) << "," << o.estimate << "," << o.truth << ","
      << o.std_error << "," << (o.parameter_estimated ? std::to_string(o.parameter_covered) : "") << ","
      << (o.improved_scored ? std::to_string(o.improved) : "") << "," << o.cv_before[0] << "," << o.cv_before[1] << ","
      << o.cv_after[0] << "," << o.cv_after[1] << "," << referenceCsv(o) << "," << o.preset << ","
      << (o.sensor_scored ? std::to_string(o.false_sensor) : "") << "," << o.seconds << ",\"" << o.error << "\","
      << o.empirical_covariate << "," << (o.empirical_scored ? std::to_string(o.empirical_ok) : "") << "," << o.cells
      << "," << o.diagnosis_seconds << "\n";
  return s.str();
}

}  // namespace diagnosis
}  // namespace tread_wear
