#include "tread_wear/fitting/calibration.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tread_wear/fitting/metrics.h"
#include "tread_wear/fitting/run_comparison.h"
#include "tread_wear/model/validation.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Bounds are physical: what a solid rubber Grosch wheel on a rig can plausibly have (Table 1 geometry;
// rubber moduli of 1-5 MPa over a 6 mm tread; friction coefficients of rubber on a rough surface).
// Where nothing tighter is known they span about an order of magnitude around the paper's Table 4 values.
const std::vector<ParameterInfo>& registry() {
  static const std::vector<ParameterInfo> entries = {
      {"a1", "m", "mm", 1e3, 5e-6, 5e-4, true, [](TireParams* p) { return &p->footprint.a1_m; }},
      {"a2", "-", "-", 1.0, 0.3, 1.5, false, [](TireParams* p) { return &p->footprint.a2; }},
      {"a3", "m", "mm", 1e3, 0.0, 5e-3, false, [](TireParams* p) { return &p->footprint.a3_m; }},
      // b <= 9 mm: half the 18 mm wheel width (Table 1).
      {"b", "m", "mm", 1e3, 5e-3, 9e-3, false, [](TireParams* p) { return &p->footprint.b_m; }},
      {"n_x", "-", "-", 1.0, 1.0, 10.0, true, [](TireParams* p) { return &p->footprint.n_x; }},
      {"lambda_x", "-", "-", 1.0, 0.0, 5.0, false, [](TireParams* p) { return &p->footprint.lambda_x; }},
      {"x_e", "m", "mm", 1e3, -2e-3, 2e-3, false, [](TireParams* p) { return &p->footprint.x_e_m; }},
      {"n_y", "-", "-", 1.0, 1.0, 10.0, true, [](TireParams* p) { return &p->footprint.n_y; }},
      {"lambda_y", "-", "-", 1.0, 0.0, 5.0, false, [](TireParams* p) { return &p->footprint.lambda_y; }},
      {"y_e", "m", "mm", 1e3, -2e-3, 2e-3, false, [](TireParams* p) { return &p->footprint.y_e_m; }},
      {"mu_0", "-", "-", 1.0, 0.1, 2.0, true, [](TireParams* p) { return &p->friction.mu_0; }},
      {"mu_m", "-", "-", 1.0, 0.2, 3.0, true, [](TireParams* p) { return &p->friction.mu_m; }},
      {"v_m", "m/s", "mm/s", 1e3, 1e-3, 1.0, true, [](TireParams* p) { return &p->friction.v_m_mps; }},
      {"h", "-", "-", 1.0, 0.05, 3.0, true, [](TireParams* p) { return &p->friction.h; }},
      {"p_0", "Pa", "MPa", 1e-6, 1e3, 2e5, true, [](TireParams* p) { return &p->friction.p_0_pa; }},
      {"p_ref", "Pa", "MPa", 1e-6, 2e4, 2e6, true, [](TireParams* p) { return &p->friction.p_ref_pa; }},
      {"q", "-", "-", 1.0, 0.0, 0.8, false, [](TireParams* p) { return &p->friction.q; }},
      {"k_y0", "Pa/m", "MPa/mm", 1e-9, 0.1e9, 5e9, true, [](TireParams* p) { return &p->tread.k_y0_pa_per_m; }},
      {"k_y1", "Pa/(m N)", "MPa/(mm N)", 1e-9, 1e5, 1e8, true,
       [](TireParams* p) { return &p->tread.k_y1_pa_per_m_n; }},
      {"phi", "-", "-", 1.0, 0.05, 2.0, true, [](TireParams* p) { return &p->tread.phi; }},
      {"c_x", "Pa s/m", "MPa/(mm/s)", 1e-9, 1e3, 1e7, true, [](TireParams* p) { return &p->tread.c_x_pa_s_per_m; }},
      {"c_y", "Pa s/m", "MPa/(mm/s)", 1e-9, 1e3, 1e7, true, [](TireParams* p) { return &p->tread.c_y_pa_s_per_m; }},
      {"m", "kg/m^2", "MPa/(mm/s^2)", 1e-9, 0.5, 200.0, true, [](TireParams* p) { return &p->tread.m_kg_per_m2; }},
      {"w1", "-", "-", 1.0, 0.0, 5.0, false, [](TireParams* p) { return &p->wear.w1; }},
      {"w2", "-", "-", 1.0, 0.0, 6.0, false, [](TireParams* p) { return &p->wear.w2; }},
      {"w3", "kg/(s m^2)", "mg/(s mm^2)", 1.0, 1e-6, 1e3, true, [](TireParams* p) { return &p->wear.w3_kg_per_s_m2; }},
      {"w4", "kg/(s m^2)", "mg/(s mm^2)", 1.0, 0.0, 1.0, false, [](TireParams* p) { return &p->wear.w4_kg_per_s_m2; }},
      {"T0", "degC", "degC", 1.0, -50.0, 250.0, false, [](TireParams* p) { return &p->wear.t0_c; }},
      {"sigma_T", "degC", "degC", 1.0, 0.5, 1000.0, true, [](TireParams* p) { return &p->wear.sigma_t_c; }},
  };
  return entries;
}

BrushOptions brushOptions(const CalibrationOptions& o) {
  BrushOptions b;
  b.grid = o.grid;
  b.orientation = o.orientation;
  b.turn_slip_iterations = o.turn_slip_iterations;
  return b;
}

bool wantsSideForce(CalibrationTarget t) { return t == CalibrationTarget::kSideForce || t == CalibrationTarget::kBoth; }
bool wantsWear(CalibrationTarget t) { return t == CalibrationTarget::kWear || t == CalibrationTarget::kBoth; }

FitMetrics metricsOf(const std::vector<CalibratedRun>& runs, double CalibratedRun::*fy, double CalibratedRun::*wr) {
  std::vector<double> mf, pf, mw, pw;
  for (const CalibratedRun& r : runs) {
    if (std::isfinite(r.measured_side_force_n) && std::isfinite(r.*fy)) {
      mf.push_back(r.measured_side_force_n);
      pf.push_back(r.*fy);
    }
    if (std::isfinite(r.measured_wear_rate_kg_per_m) && std::isfinite(r.*wr)) {
      mw.push_back(r.measured_wear_rate_kg_per_m);
      pw.push_back(r.*wr);
    }
  }
  FitMetrics m{kNaN, kNaN, kNaN, kNaN};
  if (!mf.empty()) {
    m.rmser_side_force = rmser(mf, pf);
    m.rmse_side_force_n = rmse(mf, pf);
  }
  if (!mw.empty()) {
    m.rmser_wear = rmser(mw, pw);
    m.rmse_wear_kg_per_m = rmse(mw, pw);
  }
  return m;
}

}  // namespace

const std::vector<ParameterInfo>& parameterRegistry() { return registry(); }

const ParameterInfo* findParameter(const std::string& name) {
  for (const ParameterInfo& p : registry())
    if (name == p.name) return &p;
  return nullptr;
}

namespace {
const ParameterInfo& requireParameter(const std::string& name) {
  const ParameterInfo* info = findParameter(name);
  if (info == nullptr) {
    std::string known;
    for (const ParameterInfo& p : registry()) known += std::string(known.empty() ? "" : ", ") + p.name;
    throw std::invalid_argument("unknown parameter '" + name + "'; known: " + known);
  }
  return *info;
}
}  // namespace

double getParameter(const TireParams& params, const std::string& name) {
  TireParams copy = params;
  return *requireParameter(name).field(&copy);
}

void setParameter(TireParams* params, const std::string& name, double value) {
  *requireParameter(name).field(params) = value;
}

std::vector<std::string> parseParameterList(const std::string& comma_separated) {
  std::vector<std::string> names;
  std::stringstream ss(comma_separated);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const size_t b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos) continue;
    names.push_back(item.substr(b, e - b + 1));
    requireParameter(names.back());
  }
  if (names.empty()) throw std::invalid_argument("parameter list '" + comma_separated + "' names no parameter");
  return names;
}

bool isWearLawParameter(const std::string& name) {
  return name == "w1" || name == "w2" || name == "w3" || name == "w4" || name == "T0" || name == "sigma_T";
}

const char* targetName(CalibrationTarget target) {
  switch (target) {
    case CalibrationTarget::kAuto: return "auto";
    case CalibrationTarget::kSideForce: return "side_force";
    case CalibrationTarget::kWear: return "wear";
    case CalibrationTarget::kBoth: return "both";
  }
  return "unknown";
}

bool parseTarget(const std::string& name, CalibrationTarget* target) {
  for (CalibrationTarget t : {CalibrationTarget::kAuto, CalibrationTarget::kSideForce, CalibrationTarget::kWear,
                              CalibrationTarget::kBoth})
    if (name == targetName(t)) {
      *target = t;
      return true;
    }
  return false;
}

LeastSquaresOptions CalibrationOptions::defaultSolverOptions() {
  LeastSquaresOptions o;
  o.jacobian_step = 1e-3;
  o.max_iterations = 60;
  o.function_tolerance = 1e-7;   // relative cost change: far below what changes an RMSER's 3rd digit
  o.parameter_tolerance = 1e-6;
  return o;
}

bool CalibrationOptions::validate(std::string* error) const {
  auto fail = [&](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (fit.empty()) return fail("fit: no parameter to fit");
  for (size_t i = 0; i < fit.size(); ++i) {
    if (findParameter(fit[i]) == nullptr) return fail("fit: unknown parameter '" + fit[i] + "'");
    for (size_t k = 0; k < i; ++k)
      if (fit[k] == fit[i]) return fail("fit: parameter '" + fit[i] + "' listed twice");
  }
  if (!(side_force_weight >= 0.0) || !std::isfinite(side_force_weight))
    return failValidation(error, "side_force_weight", side_force_weight, "finite and >= 0");
  if (!(wear_weight >= 0.0) || !std::isfinite(wear_weight))
    return failValidation(error, "wear_weight", wear_weight, "finite and >= 0");
  if (!(prior_weight >= 0.0) || !std::isfinite(prior_weight))
    return failValidation(error, "prior_weight", prior_weight, "finite and >= 0");
  if (turn_slip_iterations < 1)
    return failValidation(error, "turn_slip_iterations", turn_slip_iterations, ">= 1");
  std::string sub;
  if (!grid.validate(&sub)) return fail("grid: " + sub);
  if (!binning.validate(&sub)) return fail("binning: " + sub);
  if (!solver.validate(&sub)) return fail("solver: " + sub);
  return true;
}

std::vector<std::pair<double, double>> predictRuns(const TireParams& params, const RunTable& runs,
                                                   const CalibrationOptions& options) {
  const BrushWearModel model(params, brushOptions(options));
  const RunComparison cmp = compareRuns(
      runs, [&model](const OperatingPoint& op, WearResult* r) { model.evaluate(op, r); }, options.binning);
  std::vector<std::pair<double, double>> out;
  for (const RunPrediction& r : cmp.runs) out.push_back({r.side_force_n, r.wear_rate_kg_per_m});
  return out;
}

CalibrationResult calibrate(const TireParams& initial, const RunTable& runs, const CalibrationOptions& options) {
  std::string err;
  if (!options.validate(&err)) throw std::invalid_argument("calibration options: " + err);
  if (!initial.validate(&err)) throw std::invalid_argument("initial parameters: " + err);

  CalibrationResult result;
  result.options = options;
  result.target = options.target;
  if (result.target == CalibrationTarget::kAuto) {
    bool wear_only = true;
    for (const std::string& n : options.fit) wear_only = wear_only && isWearLawParameter(n);
    result.target = wear_only ? CalibrationTarget::kWear : CalibrationTarget::kBoth;
  }
  const bool use_fy = wantsSideForce(result.target), use_wr = wantsWear(result.target);
  const double fy_weight = result.target == CalibrationTarget::kBoth ? options.side_force_weight : 1.0;
  const double wr_weight = result.target == CalibrationTarget::kBoth ? options.wear_weight : 1.0;

  // Runs that measured every output the fit uses.
  std::vector<int> used;
  for (size_t i = 0; i < runs.runs.size(); ++i) {
    const RunRecord& r = runs.runs[i];
    const bool has_fy = std::isfinite(r.measured_side_force_n) && r.measured_side_force_n != 0.0;
    const bool has_wr = std::isfinite(r.measured_wear_rate_kg_per_m) && r.measured_wear_rate_kg_per_m != 0.0;
    if ((!use_fy || has_fy) && (!use_wr || has_wr)) used.push_back(static_cast<int>(i));
  }
  if (used.empty())
    throw std::invalid_argument(std::string("run table: no run has the measurements the target '") +
                                targetName(result.target) + "' needs");

  LeastSquaresProblem problem;
  problem.num_records = static_cast<int>(used.size());
  problem.residuals_per_record = (use_fy ? 1 : 0) + (use_wr ? 1 : 0);
  for (int idx : used) problem.groups.push_back(runs.runs[idx].condition_id);
  for (const std::string& name : options.fit) {
    const ParameterInfo& info = requireParameter(name);
    FitParameter p;
    p.name = name;
    p.initial = getParameter(initial, name);
    p.lower = std::min(info.lower, p.initial);
    p.upper = std::max(info.upper, p.initial);
    p.log_scale = info.log_scale && p.initial > 0.0;
    if (options.prior_weight > 0.0) {
      p.prior_value = p.initial;
      p.prior_sigma = 1.0 / options.prior_weight;
    }
    problem.parameters.push_back(p);
  }
  problem.residuals = [&](const std::vector<double>& values, const std::vector<int>& records, double* r) {
    TireParams params = initial;
    for (size_t j = 0; j < values.size(); ++j) setParameter(&params, options.fit[j], values[j]);
    if (!params.validate(nullptr)) return false;
    try {
      RunTable subset;
      for (int rec : records) subset.runs.push_back(runs.runs[used[rec]]);
      const auto pred = predictRuns(params, subset, options);
      int k = 0;
      for (size_t i = 0; i < records.size(); ++i) {
        const RunRecord& run = subset.runs[i];
        if (use_fy) r[k++] = fy_weight * (pred[i].first / run.measured_side_force_n - 1.0);
        if (use_wr) r[k++] = wr_weight * (pred[i].second / run.measured_wear_rate_kg_per_m - 1.0);
      }
    } catch (const std::exception&) {
      return false;
    }
    return true;
  };

  result.summary = solveLeastSquares(problem, options.solver);
  result.params = initial;
  if (result.summary.usable)
    for (size_t j = 0; j < options.fit.size(); ++j)
      setParameter(&result.params, options.fit[j], result.summary.parameters[j].value);

  const auto before = predictRuns(initial, runs, options);
  const auto after = predictRuns(result.params, runs, options);
  for (size_t i = 0; i < runs.runs.size(); ++i) {
    const RunRecord& r = runs.runs[i];
    result.runs.push_back({r.condition_id, r.measured_side_force_n, r.measured_wear_rate_kg_per_m, after[i].first,
                           after[i].second, kNaN, kNaN, before[i].first, before[i].second});
  }

  if (options.cross_validate) {
    const CrossValidationResult cv = crossValidate(problem, options.solver);
    result.folds = cv.folds;
    for (const CrossValidationFold& fold : cv.folds) {
      if (!fold.usable) continue;
      TireParams p = initial;
      for (size_t j = 0; j < fold.values.size(); ++j) setParameter(&p, options.fit[j], fold.values[j]);
      if (!p.validate(nullptr)) continue;
      const auto pred = predictRuns(p, runs, options);
      for (size_t i = 0; i < runs.runs.size(); ++i)
        if (runs.runs[i].condition_id == fold.group) {
          result.runs[i].cv_side_force_n = pred[i].first;
          result.runs[i].cv_wear_rate_kg_per_m = pred[i].second;
        }
    }
  }
  result.initial = metricsOf(result.runs, &CalibratedRun::initial_side_force_n,
                             &CalibratedRun::initial_wear_rate_kg_per_m);
  result.fitted = metricsOf(result.runs, &CalibratedRun::side_force_n, &CalibratedRun::wear_rate_kg_per_m);
  result.cross_validated =
      metricsOf(result.runs, &CalibratedRun::cv_side_force_n, &CalibratedRun::cv_wear_rate_kg_per_m);
  return result;
}

}  // namespace tread_wear
