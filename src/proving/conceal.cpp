#include "tread_wear/proving/conceal.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/diagnosis/user_mechanisms.h"

namespace tread_wear {
namespace diagnosis {
namespace {

constexpr double kTrackRadius_m = 0.060;    ///< R_t of the rig (Table 1)
constexpr double kHeatingC_per_W = 1.4;     ///< tread temperature rise per watt of friction power
constexpr double kTemperatureNoiseC = 2.0;  ///< run-to-run tread temperature scatter [degC]
constexpr double kAmbientSpreadC = 3.0;     ///< ambient differences between cycles [degC]
constexpr double kLoadStdFraction = 0.04;   ///< typical recorded load std / load [-]
constexpr double kThermalWearT0C = 35.0;    ///< T0 of the hidden thermal_wear term [degC]
constexpr double kW3ScaleSigma = 0.15;      ///< spread of the true w3 level (log) [-]
constexpr double kMuScaleSigma = 0.04;      ///< spread of the true friction level (log) [-]

struct Condition {
  double speed_mps, alpha_deg, load_n, duration_s;
};

const Condition kGroups[3][3] = {{{1, 10, 75, 900}, {2, 10, 75, 450}, {3, 10, 75, 300}},
                                 {{2, 5, 75, 897}, {2, 10, 75, 450}, {2, 15, 75, 303}},
                                 {{2, 10, 50, 450}, {2, 10, 75, 450}, {2, 10, 100, 450}}};
/// The low-slip program: Table 2's groups around 3 deg instead of 10 deg (sideslip 1.5/3/6 deg), durations for the
/// same lateral sliding distance (Eq 1).
const Condition kLowSlipGroups[3][3] = {{{1, 3, 75, 2987}, {2, 3, 75, 1493}, {3, 3, 75, 996}},
                                        {{2, 1.5, 75, 2985}, {2, 3, 75, 1493}, {2, 6, 75, 748}},
                                        {{2, 3, 50, 1493}, {2, 3, 75, 1493}, {2, 3, 100, 1493}}};
const char* const kGroupNames[3] = {"velocity", "sideslip", "load"};

std::string conditionId(const Condition& c) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "v%g_a%g_fz%g", c.speed_mps, c.alpha_deg, c.load_n);
  return buf;
}

}  // namespace

bool ConcealSpec::validate(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "conceal spec: " + m;
    return false;
  };
  Term t;
  const bool drives = design == "drives";
  if (effect != "none" && !parseTerm(effect, &t) && !(drives && effect == kRoughRoadEffect))
    return fail("effect = '" + effect + "' is not a library term or none" +
                (drives ? std::string(" or ") + kRoughRoadEffect : std::string()));
  if (design != "table2" && design != "small" && design != "low_slip" && !drives)
    return fail("design = '" + design + "' must be table2, small, low_slip or drives");
  if (drives) {
    std::string e;
    if (!fleet.validate(&e)) return fail(e);
  }
  if (!(wear_noise_rsd >= 0.0) || wear_noise_rsd > 0.5) return fail("wear_noise_rsd must be in [0, 0.5]");
  if (!(side_force_noise_n >= 0.0)) return fail("side_force_noise_n must be >= 0");
  if (!std::isnan(magnitude) && !std::isfinite(magnitude)) return fail("magnitude must be finite");
  return true;
}

namespace {

/// A library term's test magnitudes of its primary parameter: the default of generated cases, and the harness's
/// small and large pair.
struct TestMagnitudes {
  Term term;
  double fallback, small, large;
};
constexpr TestMagnitudes kTestMagnitudes[] = {
    {Term::kThermalWear, 30.0, 45.0, 30.0},      {Term::kThermalFriction, 0.005, 0.003, 0.006},
    {Term::kSurfacePolishing, 0.6, 0.3, 0.8},    {Term::kLateralCompliance, 3e-4, 2e-4, 4e-4},
    {Term::kPressureFriction, 0.40, 0.30, 0.50}, {Term::kLoadFluctuation, 0.25, 0.25, 0.40},
    {Term::kSensorGain, 1.08, 1.05, 1.10},       {Term::kSensorOffset, 4.0, 2.5, 5.0},
    {Term::kContactTimeWear, 3e-5, 1.5e-5, 3e-5},  // default: about 1 mg/s on a road tyre's 0.03 m^2 footprint
};

const TestMagnitudes* testMagnitudes(Term term) {
  for (const TestMagnitudes& m : kTestMagnitudes)
    if (m.term == term) return &m;
  return nullptr;
}

}  // namespace

double defaultMagnitude(Term term) {
  if (const TestMagnitudes* m = testMagnitudes(term)) return m->fallback;
  const TermInfo& info = termInfo(term);
  return info.user && !info.user->test_magnitudes.empty() ? info.user->test_magnitudes.back()
                                                          : std::numeric_limits<double>::quiet_NaN();
}

bool smallAndLargeMagnitudes(Term term, double* small, double* large) {
  if (const TestMagnitudes* m = testMagnitudes(term)) {
    *small = m->small;
    *large = m->large;
    return true;
  }
  const TermInfo& info = termInfo(term);
  if (!info.user || info.user->test_magnitudes.size() != 2) return false;
  *small = info.user->test_magnitudes[0];
  *large = info.user->test_magnitudes[1];
  return true;
}

/// The rig programme of the design (every run's conditions, covariates and placeholder measurements), with tread
/// temperatures from the base model's friction power.
void rigProgramme(const TireParams& base, const ConcealSpec& spec, Term term, double magnitude, std::mt19937_64& rng,
                  std::normal_distribution<double>& normal, std::uniform_real_distribution<double>& uniform,
                  RunTable* table) {
  table->covariate_names = {"duration_s", "ambient_c", "humidity_percent"};
  table->text_covariate_names = {"group"};
  const int cycles_per_group = spec.design == "small" ? 1 : 2;
  const auto& groups = spec.design == "low_slip" ? kLowSlipGroups : kGroups;
  int cycle = 0, order = 0;
  for (int g = 0; g < 3; ++g)
    for (int c = 0; c < cycles_per_group; ++c) {
      ++cycle;
      const double ambient = 23.0 + kAmbientSpreadC * normal(rng);
      for (int rep = 0; rep < 2; ++rep)
        for (int k = 0; k < 3; ++k) {
          const Condition& cond = groups[g][c % 2 == 0 ? k : 2 - k];
          RunRecord r;
          r.op.speed_mps = cond.speed_mps;
          r.op.slip_angle_rad = -cond.alpha_deg * M_PI / 180.0;
          r.op.path_curvature_per_m = 1.0 / kTrackRadius_m;
          r.op.load_n = cond.load_n;
          const double rel_std = term == Term::kLoadFluctuation ? magnitude : kLoadStdFraction;
          r.load_std_n = rel_std * cond.load_n * (0.5 + uniform(rng));
          r.condition_id = conditionId(cond);
          r.cycle_id = cycle;
          r.run_order = ++order;
          r.covariates = {cond.duration_s, ambient, 45.0 + 10.0 * normal(rng)};
          r.text_covariates = {kGroupNames[g]};
          r.measured_side_force_n = 1.0;  // placeholders until the truth is evaluated
          r.measured_wear_rate_kg_per_m = 1.0;
          table->runs.push_back(r);
        }
    }

  // Tread temperatures from the friction power of the base model.
  const DiagnosisData plain = buildDiagnosisData(*table);
  ExtendedModel model(base, spec.model, {}, plain);
  Prediction p;
  if (!model.predict({1.0, 1.0}, &p)) throw std::invalid_argument("the base model cannot be evaluated on the design");
  for (std::size_t i = 0; i < table->runs.size(); ++i) {
    RunRecord& r = table->runs[i];
    const double power_w = std::abs(p.side_force_n[i]) * r.op.speed_mps * std::abs(std::sin(r.op.slip_angle_rad));
    r.op.tread_temperature_c = r.covariates[1] + kHeatingC_per_W * power_w + kTemperatureNoiseC * normal(rng);
  }
}

/// The truth's parameter values: the base levels (w3_scale, mu_scale), the term at its magnitude (thermal_wear's T0
/// fixed, load_fluctuation's scale 1 with the magnitude in the recorded load std); the answer gets them.
std::vector<double> truthValues(const ExtendedModel& truth, const TireParams& base, Term term, double magnitude,
                                const double levels[2], ConcealAnswer* ans) {
  std::vector<FitParameter> params = truth.parameters();
  std::vector<double> values;
  for (const FitParameter& p : params) values.push_back(p.initial);
  values[0] = levels[0];
  values[1] = levels[1];
  if (term != Term::kNone && term != Term::kTurnSlipOrientation) {
    const TermInfo& info = termInfo(term);
    const int off = truth.parameterOffset(term);
    if (term == Term::kThermalWear) {
      values[off] = kThermalWearT0C;
      values[off + 1] = magnitude;
    } else if (term == Term::kLoadFluctuation) {
      values[off] = 1.0;
    } else {
      values[off + info.primary] = magnitude;
    }
    ans->primary = info.parameters[info.primary].name;
    ans->primary_value = values[off + info.primary];
    ans->primary_neutral = primaryNeutral(term, base);
  }
  for (std::size_t j = 0; j < params.size(); ++j) ans->parameters[params[j].name] = values[j];
  return values;
}

/// The term of `effect` ("none": kNone) and its magnitude (NaN: the term's default). @throw std::invalid_argument
/// for a term without a default magnitude when none is given.
Term effectTerm(const std::string& effect, double* magnitude) {
  Term term = Term::kNone;
  if (effect != "none" && effect != kRoughRoadEffect) parseTerm(effect, &term);
  if (term != Term::kNone && std::isnan(*magnitude)) *magnitude = defaultMagnitude(term);
  if (term != Term::kNone && std::isnan(*magnitude) && termInfo(term).primary >= 0)
    throw std::invalid_argument("effect '" + effect +
                                "' has no default magnitude: give one (--magnitude, or test_magnitudes in its file)");
  return term;
}

/// The truth's outputs on `table` (measurements set, any positive value): the base model at `levels` plus `term` at
/// `magnitude`, on the runs' cells at model.preset; the answer gets the values. check_applicable: refuse a term the
/// recordings cannot show. @throw std::invalid_argument naming the effect.
Prediction truthPrediction(const TireParams& base, const ExtendedModelOptions& model, const RunTable& table, Term term,
                           const std::string& effect, double magnitude, bool check_applicable, const double levels[2],
                           ConcealAnswer* ans) {
  const DiagnosisData data = buildDiagnosisData(table);
  if (term != Term::kNone && (check_applicable || termInfo(term).user)) {
    std::string why_not;
    if (!termApplicable(term, data, &why_not))
      throw std::invalid_argument("effect '" + effect + "' cannot be concealed in these recordings: " + why_not);
    if (termInfo(term).user) {
      Prediction plain;
      if (!ExtendedModel(base, model, {}, data).predict({1.0, 1.0}, &plain))
        throw std::invalid_argument("the base model cannot be evaluated on the recordings");
      checkNoEffect(termInfo(term), data, plain);
    }
  }
  std::vector<Term> terms;
  if (term != Term::kNone) terms.push_back(term);
  ExtendedModel truth(base, model, terms, data);
  const std::vector<double> values = truthValues(truth, base, term, magnitude, levels, ans);
  Prediction pred;
  if (!truth.predict(values, &pred)) throw std::invalid_argument("the truth model cannot be evaluated for " + effect);
  return pred;
}

ConcealCase concealEffect(const TireParams& base, const ConcealSpec& spec) {
  std::string error;
  if (!spec.validate(&error)) throw std::invalid_argument(error);
  std::mt19937_64 rng(spec.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const bool drives = spec.design == "drives";
  const bool rough_road = spec.effect == kRoughRoadEffect;
  double magnitude = spec.magnitude;
  if (rough_road && std::isnan(magnitude)) magnitude = kRoughRoadDefaultBeta;
  const Term term = effectTerm(spec.effect, &magnitude);

  ConcealCase out;
  ConcealAnswer& ans = out.answer;
  ans.effect = spec.effect;
  ans.spec = spec;
  ans.spec.magnitude = magnitude;

  RunTable& table = out.table;
  std::vector<DriveSegmentRuns> segments;
  if (drives) {
    segments = simulateDriveFleet(spec.fleet, spec.seed, &table);
    // Placeholders until the truth is evaluated (buildDiagnosisData needs measurements); no side force.
    for (RunRecord& r : table.runs) r.measured_wear_rate_kg_per_m = 1.0;
  } else {
    rigProgramme(base, spec, term, magnitude, rng, normal, uniform, &table);
  }

  // Truth.
  const double levels[2] = {std::exp(kW3ScaleSigma * normal(rng)), std::exp(kMuScaleSigma * normal(rng))};
  Prediction pred = truthPrediction(base, spec.model, table, term, spec.effect, magnitude, drives, levels, &ans);
  if (rough_road) {
    const int col =
        static_cast<int>(std::find(table.covariate_names.begin(), table.covariate_names.end(), "rough_road_share") -
                         table.covariate_names.begin());
    for (std::size_t i = 0; i < table.runs.size(); ++i)
      pred.wear_kg_per_m[i] *= 1.0 + magnitude * (table.runs[i].covariates[col] - kRoughRoadMeanShare);
    ans.primary = kRoughRoadBetaName;
    ans.primary_value = magnitude;
    ans.primary_neutral = 0.0;
    ans.parameters[kRoughRoadBetaName] = magnitude;
  }
  out.noise_free = table;
  for (std::size_t i = 0; i < table.runs.size(); ++i) {
    if (!drives) out.noise_free.runs[i].measured_side_force_n = pred.side_force_n[i];
    out.noise_free.runs[i].measured_wear_rate_kg_per_m = pred.wear_kg_per_m[i];
  }
  if (drives) {
    const std::vector<double> measured =
        measureDriveWear(segments, pred.wear_kg_per_m, spec.wear_noise_rsd, spec.fleet.depth_gauge_sigma_m,
                         base.material.massPerDepth_kg_per_m(), rng());
    for (std::size_t i = 0; i < table.runs.size(); ++i) table.runs[i].measured_wear_rate_kg_per_m = measured[i];
    return out;
  }
  for (std::size_t i = 0; i < table.runs.size(); ++i) {
    RunRecord& r = table.runs[i];
    r.measured_side_force_n = pred.side_force_n[i] + spec.side_force_noise_n * normal(rng);
    r.measured_wear_rate_kg_per_m = pred.wear_kg_per_m[i] * std::max(0.05, 1.0 + spec.wear_noise_rsd * normal(rng));
  }
  return out;
}

ConcealCase concealInRecordings(const TireParams& base, const RunTable& recordings, const std::string& effect,
                                double magnitude, const ExtendedModelOptions& model) {
  Term term = Term::kNone;
  if (effect != "none" && !parseTerm(effect, &term))
    throw std::invalid_argument("effect '" + effect + "' is not a library term or none");
  term = effectTerm(effect, &magnitude);
  ConcealCase out;
  out.answer.effect = effect;
  out.answer.spec.effect = effect;
  out.answer.spec.magnitude = magnitude;
  out.answer.spec.design = "recordings";
  out.answer.spec.model = model;
  RunTable table = recordings;
  for (RunRecord& r : table.runs) {
    r.measured_side_force_n = NAN;
    r.measured_wear_rate_kg_per_m = 1.0;  // placeholders until the truth is evaluated (buildDiagnosisData)
  }
  const double levels[2] = {1.0, 1.0};
  const Prediction pred = truthPrediction(base, model, table, term, effect, magnitude, true, levels, &out.answer);
  for (std::size_t i = 0; i < table.runs.size(); ++i) table.runs[i].measured_wear_rate_kg_per_m = pred.wear_kg_per_m[i];
  out.table = table;
  out.noise_free = table;
  return out;
}

}  // namespace diagnosis
}  // namespace tread_wear
