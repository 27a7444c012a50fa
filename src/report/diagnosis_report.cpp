#include "tread_wear/report/diagnosis_report.h"

#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tread_wear/diagnosis/user_mechanisms.h"

namespace tread_wear {
namespace diagnosis {
namespace {

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

nlohmann::json perOutput(const double* v) { return {{"side_force", num(v[0])}, {"wear", num(v[1])}}; }

nlohmann::json effectJson(const LocatedEffect& e) {
  nlohmann::json j{{"output", outputName(e.output)}, {"covariate", e.covariate},   {"kind", e.kind},
                   {"p_value", e.p_value},           {"p_adjusted", e.p_adjusted}, {"significant", e.significant}};
  if (e.categorical) {
    j["test"] = "group differences (permutation)";
    j["eta_squared"] = e.eta_squared;
    j["largest_group_difference"] = e.effect;
  } else {
    j["test"] = "Spearman trend (permutation)";
    j["spearman_rho"] = e.rho;
    j["slope_per_unit"] = e.slope;
    j["change_over_range"] = e.effect;
  }
  return j;
}

std::string pct(double v, int digits = 2) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << 100.0 * v << "%";
  return s.str();
}

std::string g(double v, int precision = 4) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

/// The empirical step (empirical.h) for diagnosis.json: what was tried and the accepted term, if any.
void addEmpirical(const EmpiricalResult& e, nlohmann::json* j) {
  nlohmann::json terms = nlohmann::json::array();
  for (const EmpiricalTerm& t : e.terms) {
    nlohmann::json parameters = nlohmann::json::array();
    for (const EmpiricalParameter& p : t.parameters)
      parameters.push_back({{"name", p.name}, {"value", p.value}, {"std_error", num(p.std_error)}, {"unit", p.unit}});
    terms.push_back({{"name", t.name},
                     {"form", t.form},
                     {"physical", false},
                     {"statement", "empirical, not physics: no library mechanism matches"},
                     {"covariate", t.covariate},
                     {"output", outputName(t.output)},
                     {"centre", t.centre},
                     {"expression", t.expression},
                     {"parameters", parameters},
                     {"rmser_before", num(t.rmser_before)},
                     {"rmser_after", num(t.rmser_after)},
                     {"held_out_rmser_before", num(t.cv_rmser_before)},
                     {"held_out_rmser_after", num(t.cv_rmser_after)},
                     {"held_out_scheme", t.cv_scheme},
                     {"f_test_p", num(t.p_value)},
                     {"aicc_drop", num(t.delta_aicc)},
                     {"summary", empiricalSummary(t)}});
  }
  (*j)["empirical_terms"] = terms;
  if (!e.attempted) return;
  (*j)["empirical"] = {{"covariates_tried", e.covariates},
                       {"covariate", e.covariate},
                       {"output", e.covariate.empty() ? nlohmann::json() : nlohmann::json(outputName(e.output))},
                       {"family", e.family},
                       {"reason", e.reason},
                       {"selection", e.log}};
}

std::string effectText(const LocatedEffect& e) {
  std::ostringstream s;
  if (e.categorical)
    s << "eta^2 = " << g(e.eta_squared, 3) << ", largest group difference " << pct(e.effect, 1) << " points";
  else
    s << "rho = " << g(e.rho, 3) << ", change over the range " << pct(e.effect, 1) << " points";
  return s.str();
}

/// Each output's noise model: as selected (kind, source, AICc of each kind) and as weighted in the last step.
nlohmann::json noiseModelsJson(const DiagnosisResult& r) {
  nlohmann::json j = nlohmann::json::object();
  for (int o = 0; o < kNumOutputs; ++o) {
    const NoiseSelection& s = r.noise[o];
    const NoiseModel& w = r.weights[o];
    nlohmann::json aicc = nlohmann::json::object();
    for (int k = 0; k < kNumNoiseKinds; ++k) aicc[noiseKindName(static_cast<NoiseKind>(k))] = num(s.aicc[k]);
    j[outputName(static_cast<Output>(o))] = {{"kind", noiseKindName(s.model.kind)},
                                             {"selected_by_aicc", s.selected},
                                             {"source", s.source},
                                             {"aicc", aicc},
                                             {"combined_shape", s.combined_shape},
                                             {"additive", w.additive},
                                             {"relative", w.relative}};
  }
  return j;
}

/// "Time per step": wall time and brush evaluations of each step of the diagnosis ("" without timings).
std::string timingsMarkdown(const DiagnosisResult& r) {
  if (r.timings.empty()) return "";
  std::ostringstream m;
  m << "\n## Time per step\n\n| step | preset | wall time [s] | brush evaluations |\n|---|---|---|---|\n";
  for (const StepTiming& t : r.timings)
    m << "| " << t.step << " | " << presetName(t.preset) << " | " << g(t.seconds, 3) << " | " << t.cells_evaluated
      << " |\n";
  m << "| **total** | | **" << g(r.seconds, 3) << "** | |\n";
  return m.str();
}

/// The solver-error checks and the decision on the preset (numerics_check.h).
nlohmann::json numericsJson(const DiagnosisResult& r) {
  nlohmann::json checks = nlohmann::json::array();
  for (const NumericsCheck& c : r.numerics) {
    nlohmann::json outputs = nlohmann::json::object();
    for (int o = 0; o < kNumOutputs; ++o) {
      const NumericsOutput& n = c.outputs[o];
      outputs[outputName(static_cast<Output>(o))] = {{"values", n.values},
                                                     {"rms_error_in_noise_std", n.rms_in_noise},
                                                     {"rms_relative_error", n.rms_relative},
                                                     {"max_relative_error", n.max_relative},
                                                     {"noncentrality_unprojected", n.noncentrality_raw}};
    }
    checks.push_back({{"preset", presetName(c.preset)},
                      {"compared_with", presetName(c.finer)},
                      {"checked", c.checked},
                      {"at_model", c.at_model},
                      {"noncentrality", c.noncentrality},
                      {"limit", c.limit},
                      {"passed", c.passed},
                      {"drive_cells", c.cells},
                      {"cells_compared", c.cells_compared},
                      {"sampled", c.sampled},
                      {"confidence", c.confidence},
                      {"noncentrality_interval", {c.noncentrality_low, c.noncentrality_high}},
                      {"seconds", c.seconds},
                      {"outputs", outputs}});
  }
  return {{"preset", presetName(r.preset)},
          {"decision", r.numerics_decision},
          {"warning", r.numerics_warning},
          {"checks", checks}};
}

/// The verdict and its evidence (diagnosisJson's document).
nlohmann::json diagnosisDocument(const DiagnosisResult& r, const DiagnosisData& data) {
  nlohmann::json j;
  j["format"] = "tread_wear diagnosis v1";
  j["mismatch_found"] = r.mismatch_found;
  j["explanation"] = r.explanation;
  nlohmann::json terms = nlohmann::json::array();
  for (Term t : r.final_model.terms) {
    const TermInfo& info = termInfo(t);
    nlohmann::json outputs = nlohmann::json::array();
    for (int o = 0; o < kNumOutputs; ++o)
      if (info.affects[o]) outputs.push_back(outputName(static_cast<Output>(o)));
    nlohmann::json parameters = nlohmann::json::array();
    for (const TermParameterSpec& p : info.parameters)
      parameters.push_back({{"name", p.name}, {"unit", p.unit}, {"no_effect", num(p.neutral)}});
    nlohmann::json term{{"name", info.name},
                        {"statement", info.statement},
                        {"physical", info.physical},
                        {"outputs", outputs},
                        {"parameters", parameters}};
    if (info.user) term["defined_in"] = info.user->where();
    terms.push_back(term);
  }
  j["explanation_terms"] = terms;
  nlohmann::json located = nlohmann::json::array(), tests = nlohmann::json::array();
  for (const LocatedEffect& e : r.located_before) {
    if (e.significant) located.push_back(effectJson(e));
    tests.push_back(effectJson(e));
  }
  j["located"] = located;
  j["locating_tests"] = tests;
  nlohmann::json after = nlohmann::json::array();
  for (const LocatedEffect& e : r.located_after)
    if (e.significant) after.push_back(effectJson(e));
  j["remaining_after"] = after;
  j["unexplained_covariates"] = r.unexplained_covariates;
  nlohmann::json alternatives = nlohmann::json::array();
  for (const CloseAlternative& a : r.close_alternatives)
    alternatives.push_back({{"model", a.model}, {"instead_of", a.instead_of}, {"delta_aicc", a.delta_aicc}});
  j["close_alternatives"] = alternatives;
  addEmpirical(r.empirical, &j);
  nlohmann::json params = nlohmann::json::object();
  for (const ParameterEstimate& p : r.final_model.summary.parameters)
    params[p.name] = {
        {"value", p.value}, {"std_error", num(p.std_error)}, {"unit", parameterUnit(p.name)}, {"lower", p.lower},
        {"upper", p.upper}, {"at_bound", p.atBound()}};
  j["parameters"] = params;
  j["condition_number"] = num(r.final_model.summary.condition_number);
  j["rmser_before"] = perOutput(r.base.rmser);
  j["rmser_after"] = perOutput(r.final_model.rmser);
  j["cv_rmser_before"] = perOutput(r.base.cv_rmser);
  j["cv_rmser_after"] = perOutput(r.final_model.cv_rmser);
  j["cv_scheme"] = r.cv_scheme;
  nlohmann::json shift = nlohmann::json::object();
  for (const char* name : {"w3_scale", "mu_scale"}) {
    const double before = fittedValue(r.base, name), after = fittedValue(r.final_model, name);
    shift[name] = {{"before", before}, {"after", after}, {"relative", after / before - 1.0}};
  }
  j["base_parameter_shift"] = shift;
  nlohmann::json cands = nlohmann::json::array();
  for (const FittedModel& f : r.tried) {
    nlohmann::json c{{"model", f.label},           {"extends", f.parent},
                     {"usable", f.usable},         {"k", f.k},
                     {"weighted_rss", num(f.rss)}, {"aicc", num(f.aicc)},
                     {"bic", num(f.bic)},          {"p_vs_parent", num(f.p_vs_parent)},
                     {"eligible", f.eligible},     {"rmser", perOutput(f.rmser)}};
    if (f.cv_done) c["cv_rmser"] = perOutput(f.cv_rmser);
    if (std::isfinite(f.p_held_out)) c["p_held_out_vs_parent"] = f.p_held_out;
    nlohmann::json pv = nlohmann::json::object();
    for (const ParameterEstimate& p : f.summary.parameters)
      pv[p.name] = {{"value", p.value}, {"std_error", num(p.std_error)}};
    c["parameters"] = pv;
    cands.push_back(c);
  }
  j["candidates"] = cands;
  j["noise_models"] = noiseModelsJson(r);
  j["numerics"] = numericsJson(r);
  nlohmann::json timings = nlohmann::json::array();
  for (const StepTiming& t : r.timings)
    timings.push_back({{"step", t.step},
                       {"preset", presetName(t.preset)},
                       {"seconds", t.seconds},
                       {"cells_evaluated", t.cells_evaluated}});
  j["timings"] = {{"total_seconds", r.seconds}, {"steps", timings}};
  j["noise_left"] = {{"side_force_n", num(r.side_force_noise_n)}, {"wear_rsd", num(r.wear_noise_rsd)}};
  if (!r.detection_limits.empty()) {
    nlohmann::json limits = nlohmann::json::object();
    for (const DetectionLimit& l : r.detection_limits)
      limits[l.term] = {{"parameter", l.parameter}, {"no_effect_value", num(l.neutral)},   {"below", num(l.below)},
                        {"above", num(l.above)},    {"switch_power", num(l.switch_power)}, {"note", l.note}};
    j["detection_limits"] = {{"power", r.detection_power}, {"terms", limits}};
  }
  j["repeat_spread"] = perOutput(r.pure_error);
  j["skipped_terms"] = r.skipped_terms;
  j["data_warnings"] = data.warnings;
  j["not_located"] = r.not_located;
  j["not_located_after"] = r.not_located_after;
  j["selection_log"] = r.log;
  j["runs"] = data.runs.size();
  j["measured"] = {{"side_force", data.measured_count[0]}, {"wear", data.measured_count[1]}};
  // The covariate each output's plot shows: the most significant locating test of that output, or the empirical
  // term's covariate for the output it modifies.
  nlohmann::json plot = nlohmann::json::object();
  for (int o = 0; o < kNumOutputs; ++o)
    for (const LocatedEffect& e : r.located_before)
      if (static_cast<int>(e.output) == o) {
        plot[outputName(e.output)] = e.covariate;
        break;
      }
  for (const EmpiricalTerm& t : r.empirical.terms) plot[outputName(t.output)] = t.covariate;
  j["plot_covariates"] = plot;
  return j;
}

/// A detectability reference (answerJson's "detectability").
nlohmann::json detectabilityDocument(const Detectability& d) {
  nlohmann::json j;
  j["lambda"] = d.lambda;
  j["power"] = num(d.power);
  j["expected_right"] = d.expected_right;
  j["terms_tried"] = d.terms_tried;
  for (const OracleVerdict& v : d.verdicts) j["verdicts"][v.verdict] = v.probability;
  for (const ReferenceParameter& p : d.parameters)
    j["parameters"][p.name] = {{"value", p.value}, {"std_error", num(p.std_error)}};
  return j;
}

}  // namespace

std::string diagnosisJson(const DiagnosisResult& result, const DiagnosisData& data) {
  return diagnosisDocument(result, data).dump(2) + "\n";
}

namespace {

/// The verdict with its terms, close alternatives, empirical terms and the errors before and after.
void verdictSection(std::ostream& m, const DiagnosisResult& r, const DiagnosisData& data) {
  m << "## Verdict\n\n";
  m << "- mismatch found: **" << (r.mismatch_found ? "yes" : "no") << "**\n";
  m << "- explanation: **" << r.explanation << "**\n";
  for (Term t : r.final_model.terms) {
    const TermInfo& info = termInfo(t);
    m << "  - `" << info.name << "`" << (info.physical ? "" : " (sensor, not physics)")
      << (info.user ? " (user-defined, " + info.user->where() + ")" : "") << ": " << info.statement << "\n";
  }
  for (const CloseAlternative& a : r.close_alternatives)
    m << "- about as well supported: `" << a.model << "` instead of `" << a.instead_of << "` (AICc "
      << (a.delta_aicc >= 0.0 ? "+" : "") << g(a.delta_aicc, 2)
      << "): these recordings cannot tell the two apart; runs that separate them would (for a sensor gain and "
         "offset: low side forces, or a zero-load check of the transducer)\n";
  if (!r.unexplained_covariates.empty()) {
    m << "- no library term explains it; the residual follows:";
    for (const std::string& c : r.unexplained_covariates) m << " `" << c << "`";
    m << "\n";
  }
  for (const EmpiricalTerm& t : r.empirical.terms)
    m << "- empirical model (not physics): " << empiricalSummary(t) << "; no library mechanism matches\n";
  if (r.empirical.attempted && r.empirical.terms.empty()) m << "- no empirical term: " << r.empirical.reason << "\n";
  for (const std::string& w : data.warnings) m << "- data warning: " << w << "\n";
  m << "\n| | side force RMSER | wear RMSER | side force held out | wear held out |\n|---|---|---|---|---|\n";
  m << "| base model (calibrated levels) | " << pct(r.base.rmser[0]) << " | " << pct(r.base.rmser[1]) << " | "
    << pct(r.base.cv_rmser[0]) << " | " << pct(r.base.cv_rmser[1]) << " |\n";
  m << "| " << r.final_model.label << " | " << pct(r.final_model.rmser[0]) << " | " << pct(r.final_model.rmser[1])
    << " | " << pct(r.final_model.cv_rmser[0]) << " | " << pct(r.final_model.cv_rmser[1]) << " |\n\n";
  m << "Held out: " << r.cv_scheme << ". RMSER is Eq 24 of the paper.\n\n";
}

/// The empirical terms' table (after "unexplained").
void empiricalSection(std::ostream& m, const DiagnosisResult& r) {
  if (!r.empirical.terms.empty()) {
    m << "## Empirical terms (not physics)\n\n";
    m << "No library term explains the mismatch; the terms below describe the recordings in `" << r.empirical.covariate
      << "` (family tried: ";
    for (std::size_t i = 0; i < r.empirical.family.size(); ++i)
      m << (i ? ", " : "") << "`" << r.empirical.family[i] << "`";
    m << "), selected as the library terms are (F test, AICc, held-out error: " << r.empirical.terms.front().cv_scheme
      << ").\n\n";
    m << "| term | expression | parameters | F test p | AICc drop | RMSER | held out "
         "|\n|---|---|---|---|---|---|---|\n";
    for (const EmpiricalTerm& t : r.empirical.terms) {
      m << "| `" << t.name << "` | `" << t.expression << "` | ";
      for (std::size_t i = 0; i < t.parameters.size(); ++i)
        m << (i ? "; " : "") << t.parameters[i].name << " = " << g(t.parameters[i].value, 3) << " +- "
          << g(t.parameters[i].std_error, 2) << " " << t.parameters[i].unit;
      m << " | " << g(t.p_value, 2) << " | " << g(t.delta_aicc, 3) << " | " << pct(t.rmser_before) << " -> "
        << pct(t.rmser_after) << " | " << pct(t.cv_rmser_before) << " -> " << pct(t.cv_rmser_after) << " |\n";
    }
    m << "\n";
  }
}

/// The locating tests on the base model's residuals.
void locateSection(std::ostream& m, const DiagnosisResult& r) {
  m << "## Where the base model misses (tests on the residuals standardised by the noise model; effects in points of "
       "predicted/measured - 1)\n\n";
  m << "Permutation tests, Holm-adjusted over all " << r.located_before.size() << " tests; ten smallest p-values:\n\n";
  for (const std::string& why : r.not_located) m << "Not tested: " << why << ".\n\n";
  m << "| output | covariate | kind | effect | p | p (Holm) |\n|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < r.located_before.size() && i < 10; ++i) {
    const LocatedEffect& e = r.located_before[i];
    m << "| " << outputName(e.output) << " | `" << e.covariate << "` | " << e.kind << " | " << effectText(e) << " | "
      << g(e.p_value, 2) << " | " << (e.significant ? "**" : "") << g(e.p_adjusted, 2) << (e.significant ? "**" : "")
      << " |\n";
  }
}

/// Every model fitted, the terms not applicable and the selection log.
void candidatesSection(std::ostream& m, const DiagnosisResult& r) {
  m << "\n## Candidate extensions tried\n\n";
  m << "| model | extends | params | AICc | BIC | F test p | eligible | held-out Fy | held-out W_r |\n"
       "|---|---|---|---|---|---|---|---|---|\n";
  m << "| base | | " << r.base.k << " | " << g(r.base.aicc) << " | " << g(r.base.bic) << " | | | "
    << pct(r.base.cv_rmser[0]) << " | " << pct(r.base.cv_rmser[1]) << " |\n";
  for (const FittedModel& f : r.tried)
    m << "| " << f.label << " | " << f.parent << " | " << f.k << " | " << g(f.aicc) << " | " << g(f.bic) << " | "
      << g(f.p_vs_parent, 2) << " | " << (f.eligible ? "yes" : "no") << " | " << (f.cv_done ? pct(f.cv_rmser[0]) : "")
      << " | " << (f.cv_done ? pct(f.cv_rmser[1]) : "") << " |\n";
  m << "\nEach candidate is fitted with the output weights of the model it extends (relative residuals divided by "
       "that model's RMSER per output); an accepted model is refitted with its own, so the verdict's numbers differ "
       "slightly from its row here.\n";
  if (!r.skipped_terms.empty()) {
    m << "\nNot applicable to these recordings:\n";
    for (const std::string& s : r.skipped_terms) m << "- " << s << "\n";
  }
  m << "\nSelection:\n";
  for (const std::string& l : r.log) m << "- " << l << "\n";
}

/// The detection limits (step 6).
void detectionLimitsSection(std::ostream& m, const DiagnosisResult& r) {
  if (!r.detection_limits.empty()) {
    m << "\n## What these recordings could have shown\n\n";
    m << "The smallest effect of each term that the first selection step would find with probability "
      << g(r.detection_power, 6) << ", added to the calibrated base model, at the noise the final model leaves ("
      << (std::isfinite(r.side_force_noise_n) ? g(r.side_force_noise_n, 3) + " N" : std::string("not measured:"))
      << " side force, " << (std::isfinite(r.wear_noise_rsd) ? pct(r.wear_noise_rsd) : std::string("not measured:"))
      << " wear). Effects beyond these "
      << "values would have been found that often; smaller ones can hide in these recordings"
      << (r.explanation == "none" ? ", so `none` rules out only the larger ones" : "")
      << ". Found means that the step's F test flags the term against the base model; near its limit a term can "
         "still lose to a look-alike that fits about as well (a small gain to an offset).\n\n";
    m << "| term | parameter | no effect at | detectable below | detectable above | note |\n"
         "|---|---|---|---|---|---|\n";
    for (const DetectionLimit& l : r.detection_limits) {
      m << "| " << l.term << " | " << l.parameter << " | "
        << (!l.parameter.empty() && std::isnan(l.neutral) ? std::string("infinity") : g(l.neutral, 4)) << " | "
        << g(l.below, 3) << " | " << g(l.above, 3) << " | " << l.note;
      if (std::isfinite(l.switch_power)) m << "power of the switch " << g(l.switch_power, 2);
      m << " |\n";
    }
    m << "\nthermal_wear: sigma_T with T0 at the coldest run; load_fluctuation: multiples of the recorded load std.\n";
  }
}

/// The selected model's parameters and what its residuals still follow.
void parametersSection(std::ostream& m, const DiagnosisResult& r) {
  m << "\n## Parameters of the selected model\n\n| parameter | unit | value | std error | at bound |\n"
       "|---|---|---|---|---|\n";
  for (const ParameterEstimate& p : r.final_model.summary.parameters)
    m << "| " << p.name << " | " << parameterUnit(p.name) << " | " << g(p.value, 5) << " | " << g(p.std_error, 3)
      << " | " << (p.atBound() ? "yes" : "") << " |\n";
  m << "\nBase parameter shift once the terms were added: ";
  for (const char* name : {"w3_scale", "mu_scale"})
    m << name << " " << g(fittedValue(r.base, name), 4) << " -> " << g(fittedValue(r.final_model, name), 4) << "; ";
  m << "condition number " << g(r.final_model.summary.condition_number, 3) << ".\n";
  const bool remaining =
      std::any_of(r.located_after.begin(), r.located_after.end(), [](const LocatedEffect& e) { return e.significant; });
  m << "\nAfter the selected model, "
    << (remaining ? "the residual still follows:" : "no locating test is significant.");
  for (const LocatedEffect& e : r.located_after)
    if (e.significant) m << " " << outputName(e.output) << "/`" << e.covariate << "`";
  m << "\n";
  for (const std::string& why : r.not_located_after) m << "\nNot tested after: " << why << ".\n";
}

/// The preset decision, the solver-error checks and the noise models.
void numericsSection(std::ostream& m, const DiagnosisResult& r) {
  m << "\n## Numerics and noise model\n\n";
  m << "- preset: **" << presetName(r.preset) << "**: " << r.numerics_decision << "\n";
  if (!r.numerics_warning.empty()) m << "- **warning**: " << r.numerics_warning << "\n";
  for (const NumericsCheck& c : r.numerics)
    if (c.checked)
      m << "  - " << presetName(c.preset) << " vs " << presetName(c.finer) << " at `" << c.at_model << "`: lambda "
        << g(c.noncentrality, 3) << " (limit " << g(c.limit, 3) << ", " << (c.passed ? "passed" : "failed")
        << "); side force " << g(c.outputs[0].rms_in_noise, 3) << " noise std RMS (" << pct(c.outputs[0].rms_relative)
        << " RMS, largest " << pct(c.outputs[0].max_relative) << "), wear " << g(c.outputs[1].rms_in_noise, 3)
        << " noise std RMS (" << pct(c.outputs[1].rms_relative) << " RMS, largest " << pct(c.outputs[1].max_relative)
        << ")"
        << (c.sampled ? "; estimated from " + std::to_string(c.cells_compared) + " of " + std::to_string(c.cells) +
                            " drive cells, lambda in " + g(c.noncentrality_low, 3) + "-" + g(c.noncentrality_high, 3) +
                            " at " + g(100.0 * c.confidence, 3) + "% confidence"
                      : std::string())
        << " (" << g(c.seconds, 3) << " s)\n";
  for (int o = 0; o < kNumOutputs; ++o) {
    const NoiseSelection& s = r.noise[o];
    const NoiseModel& w = r.weights[o];
    m << "- noise model of " << outputName(static_cast<Output>(o)) << ": **" << noiseKindName(s.model.kind) << "** ("
      << (s.selected ? "lowest AICc" : "given") << " on " << s.source << "; AICc additive " << g(s.aicc[0], 5)
      << ", relative " << g(s.aicc[1], 5) << ", combined " << g(s.aicc[2], 5) << "); weights sigma = sqrt("
      << g(w.additive, 3) << "^2 + (" << g(w.relative, 3) << " y)^2)\n";
  }
  m << "\nSpread of repeats " << pct(r.pure_error[0]) << " / " << pct(r.pure_error[1])
    << " (side force / wear, relative). With few runs the F test and AICc are indicative only.\n";
}

}  // namespace

std::string diagnosisMarkdown(const DiagnosisResult& r, const DiagnosisData& data, const std::string& source,
                              const std::vector<std::string>& plots) {
  std::ostringstream m;
  m << "# Mismatch diagnosis\n\n";
  m << "Recordings: `" << source << "` (" << data.runs.size() << " runs; side force measured in "
    << data.measured_count[0] << ", wear in " << data.measured_count[1] << ").\n\n";
  verdictSection(m, r, data);
  empiricalSection(m, r);
  locateSection(m, r);
  candidatesSection(m, r);
  detectionLimitsSection(m, r);
  parametersSection(m, r);
  if (!plots.empty()) {
    m << "\n## Plots\n\n";
    for (const std::string& p : plots) m << "![" << p << "](" << p << ")\n\n";
  }
  numericsSection(m, r);
  m << timingsMarkdown(r);
  return m.str();
}

std::string residualsCsv(const DiagnosisResult& r, const DiagnosisData& data) {
  std::ostringstream c;
  c << std::setprecision(10);
  c << "run,condition_id,measured_side_force_n,measured_wear_kg_per_m,predicted_side_force_n_before,"
       "predicted_wear_kg_per_m_before,predicted_side_force_n_after,predicted_wear_kg_per_m_after,"
       "residual_side_force_before,residual_wear_before,residual_side_force_after,residual_wear_after";
  for (const Covariate& cov : data.covariates) c << "," << cov.name;
  // With an empirical term: its relative residuals of the output it modifies, last.
  const EmpiricalTerm* empirical = r.empirical.terms.empty() ? nullptr : &r.empirical.terms.front();
  if (empirical) c << ",residual_" << outputName(empirical->output) << "_empirical";
  c << "\n";
  std::vector<double> res[2][2];
  for (int o = 0; o < kNumOutputs; ++o) {
    res[0][o] = relativeResiduals(data, r.base.prediction, static_cast<Output>(o));
    res[1][o] = relativeResiduals(data, r.final_model.prediction, static_cast<Output>(o));
  }
  auto cell = [](double v) { return std::isfinite(v) ? g(v, 10) : std::string(); };
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    const DiagnosisRun& run = data.runs[i];
    c << i + 1 << ",\"" << run.condition << "\"," << cell(run.measured[0]) << "," << cell(run.measured[1]) << ","
      << cell(r.base.prediction.side_force_n[i]) << "," << cell(r.base.prediction.wear_kg_per_m[i]) << ","
      << cell(r.final_model.prediction.side_force_n[i]) << "," << cell(r.final_model.prediction.wear_kg_per_m[i]) << ","
      << cell(res[0][0][i]) << "," << cell(res[0][1][i]) << "," << cell(res[1][0][i]) << "," << cell(res[1][1][i]);
    for (const Covariate& cov : data.covariates)
      c << "," << (cov.categorical ? "\"" + cov.levels[static_cast<int>(cov.values[i])] + "\"" : cell(cov.values[i]));
    if (empirical) c << "," << cell(empirical->prediction[i] / run.measured[static_cast<int>(empirical->output)] - 1.0);
    c << "\n";
  }
  return c.str();
}

std::string answerJson(const ConcealAnswer& a, const Detectability* reference) {
  nlohmann::json j;
  j["effect"] = a.effect;
  j["parameters"] = a.parameters;
  j["primary"] = a.primary;
  j["primary_value"] = std::isfinite(a.primary_value) ? nlohmann::json(a.primary_value) : nlohmann::json();
  j["primary_neutral"] = std::isfinite(a.primary_neutral) ? nlohmann::json(a.primary_neutral) : nlohmann::json();
  j["design"] = a.spec.design;
  j["magnitude"] = std::isfinite(a.spec.magnitude) ? nlohmann::json(a.spec.magnitude) : nlohmann::json();
  j["wear_noise_rsd"] = a.spec.wear_noise_rsd;
  j["side_force_noise_n"] = a.spec.side_force_noise_n;
  j["seed"] = a.spec.seed;
  if (reference != nullptr) j["detectability"] = detectabilityDocument(*reference);
  return j.dump(2) + "\n";
}

}  // namespace diagnosis
}  // namespace tread_wear
