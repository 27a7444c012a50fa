#include "tread_wear/diagnosis/extensions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>

#include "tread_wear/diagnosis/user_mechanisms.h"
#include "tread_wear/model/adhesion_wear.h"
#include "tread_wear/model/contact_patch.h"
#include "tread_wear/model/point_cells.h"

namespace tread_wear {
namespace diagnosis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Base level parameters, always free: [w3_scale, mu_scale].
constexpr int kBaseParameters = 2;
/// Brush results kept for this many distinct brush-relevant parameter vectors before the cache is reset.
constexpr std::size_t kCacheEntries = 64;
/// Compliance root: |alpha_eff - alpha - c Fy| below this [rad] (0.0001 deg) ends the secant iteration.
constexpr double kComplianceTolerance_rad = 2e-6;
/// thermal_friction evaluates one brush model per tread temperature rounded to this [degC].
constexpr double kThermalFrictionResolution_c = 0.1;
constexpr int kComplianceIterations = 12;

std::vector<TermInfo> makeLibrary() {
  std::vector<TermInfo> lib;
  lib.push_back({Term::kThermalWear, "thermal_wear",
                 "abrasion resistance depends on the tread temperature: w3 -> w3 exp((T - T0)^2 / (2 sigma_T^2)) "
                 "(Eq 25)",
                 true, {false, true},
                 {{"t0_c", 40.0, -50.0, 200.0, false, kNaN, "degC"},
                  {"sigma_t_c", 30.0, 2.0, 1000.0, true, kNaN, "degC"}},
                 1});
  lib.push_back({Term::kThermalFriction, "thermal_friction",
                 "rubber friction falls as the tread warms: mu_0, mu_m -> (1 - k_T (T - 23 degC)) mu_0, mu_m", true,
                 {true, true}, {{"k_t_per_k", 0.0, -0.015, 0.015, false, 0.0, "1/K"}}, 0});
  lib.push_back({Term::kSurfacePolishing, "surface_polishing",
                 "the track gets polished: abrasiveness decays as exp(-r_p L) with the sliding distance L on the "
                 "current surface, reset when the surface is renewed (each cycle)",
                 true, {false, true}, {{"polishing_rate_per_km", 0.2, 0.0, 10.0, false, 0.0, "1/km"}}, 0});
  lib.push_back({Term::kLateralCompliance, "lateral_compliance",
                 "the wheel or carcass bends under the side force, lowering the effective slip angle: "
                 "|alpha_eff| = |alpha| - c_lat |Fy|",
                 true, {true, true}, {{"compliance_rad_per_n", 1e-4, 0.0, 3e-3, false, 0.0, "rad/N"}}, 0});
  lib.push_back({Term::kPressureFriction, "pressure_friction",
                 "friction falls with contact pressure more (or less) than the file says: the sat(p) exponent q "
                 "of Eq 11 is free",
                 true, {true, true}, {{"q", 0.14, 0.0, 1.0, false, 0.14, "-"}}, 0});
  lib.push_back({Term::kLoadFluctuation, "load_fluctuation",
                 "the vertical load fluctuates during a run: forces and wear are the Eq 23 average over "
                 "N(Fz, (s_load load_std)^2) instead of the value at the mean load",
                 true, {true, true}, {{"load_std_scale", 1.0, 0.0, 6.0, false, 0.0, "-"}}, 0});
  lib.push_back({Term::kTurnSlipOrientation, "turn_slip_orientation",
                 "the slip angle is oriented the other way against the track curve (turn slip adds to sideslip "
                 "instead of opposing it)",
                 true, {true, true}, {}, -1});
  lib.push_back({Term::kSensorGain, "sensor_gain",
                 "not physics: the side-force transducer reads g times the true force (calibration gain error)",
                 false, {true, false}, {{"side_force_gain", 1.0, 0.5, 1.5, false, 1.0, "-"}}, 0});
  lib.push_back({Term::kSensorOffset, "sensor_offset",
                 "not physics: the side-force transducer reads the true force plus a constant zero offset o [N]",
                 false, {true, false}, {{"side_force_offset_n", 0.0, -30.0, 30.0, false, 0.0, "N"}}, 0});
  lib.push_back({Term::kContactTimeWear,
                 "contact_time_wear",
                 "the tread wears per unit contact time and area, sliding or not (Eq 19's w4 term): W_r += w4 4ab / V",
                 true,
                 {false, true},
                 {{"w4_kg_per_s_m2", 1e-5, 0.0, 1e-3, false, 0.0, "kg/(s m^2)"}},
                 0});
  lib.push_back({Term::kAdhesionWear,
                 "adhesion_wear",
                 "micro-slip on the road texture wears the tread in the adhesion zone: W_r += K_a E_a, E_a the shear "
                 "work turned over there per distance (model/adhesion_wear.h)",
                 true,
                 {false, true},
                 {{"adhesion_kg_per_j", 1e-9, 0.0, 1e-6, false, 0.0, "kg/J"}},
                 0});
  return lib;
}

std::vector<TermInfo>& library() {
  static std::vector<TermInfo> lib = makeLibrary();
  return lib;
}

/// The calling thread's own library while set (setThreadLibrary), else null.
thread_local const std::vector<TermInfo>* t_thread_library = nullptr;

}  // namespace

const std::vector<TermInfo>& termLibrary() { return t_thread_library ? *t_thread_library : library(); }

const std::vector<TermInfo>* setThreadLibrary(const std::vector<TermInfo>* lib) {
  const std::vector<TermInfo>* previous = t_thread_library;
  t_thread_library = lib;
  return previous;
}

std::vector<TermInfo> setUserTerms(std::vector<TermInfo> user) {
  std::vector<TermInfo>& lib = library();
  const auto first_user = lib.begin() + static_cast<int>(Term::kFirstUser);
  std::vector<TermInfo> previous(std::make_move_iterator(first_user), std::make_move_iterator(lib.end()));
  lib.erase(first_user, lib.end());
  for (TermInfo& t : user) {
    t.term = static_cast<Term>(lib.size());
    lib.push_back(std::move(t));
  }
  return previous;
}

const TermInfo& termInfo(Term term) { return termLibrary().at(static_cast<int>(term)); }

bool neutralOnBound(const TermInfo& info) {
  if (info.parameters.size() != 1) return false;
  const TermParameterSpec& p = info.parameters.front();
  return p.neutral == p.lower || p.neutral == p.upper;
}

double primaryNeutral(Term term, const TireParams& base) {
  const TermInfo& info = termInfo(term);
  if (info.primary < 0) return kNaN;
  return term == Term::kPressureFriction ? base.friction.q : info.parameters[info.primary].neutral;
}

bool parseTerm(const std::string& name, Term* term) {
  for (const TermInfo& t : termLibrary())
    if (t.name == name) {
      *term = t.term;
      return true;
    }
  return false;
}

std::string parameterUnit(const std::string& name) {
  if (name == "w3_scale" || name == "mu_scale") return "-";
  for (const TermInfo& t : termLibrary())
    for (const TermParameterSpec& p : t.parameters)
      if (p.name == name) return p.unit;
  return "";
}

std::string termsLabel(const std::vector<Term>& terms) {
  if (terms.empty()) return "none";
  std::string s;
  for (Term t : terms) s += (s.empty() ? "" : "+") + termInfo(t).name;
  return s;
}

bool termApplicable(Term term, const DiagnosisData& data, std::string* why_not) {
  auto no = [&](const std::string& why) {
    if (why_not) *why_not = why;
    return false;
  };
  const bool fy = data.measured_count[0] > 0;
  switch (term) {
    case Term::kThermalWear:
      if (!data.has_temperature) return no("no tread temperature recorded in every run");
      if (data.measured_count[1] == 0) return no("no wear measured");
      return true;
    case Term::kThermalFriction:
      return data.has_temperature ? true : no("no tread temperature recorded in every run");
    case Term::kSurfacePolishing:
      if (!data.has_sequence) return no("no sequence: needs cycle_id or run_order and distance_m or duration_s");
      if (data.measured_count[1] == 0) return no("no wear measured");
      return true;
    case Term::kLoadFluctuation:
      return data.has_load_std ? true : no("no load standard deviation recorded");
    case Term::kTurnSlipOrientation:
      return data.has_turn_slip ? true : no("no run has a path curvature (turn slip)");
    case Term::kSensorGain:
    case Term::kSensorOffset:
      return fy ? true : no("no side force measured");
    case Term::kContactTimeWear:
    case Term::kAdhesionWear: {
      const bool drives =
          std::any_of(data.runs.begin(), data.runs.end(), [](const DiagnosisRun& r) { return r.isDrive(); });
      if (!drives) return no("a road term: needs drive segments (extensions.h)");
      return data.measured_count[1] > 0 ? true : no("no wear measured");
    }
    default:
      return termInfo(term).user ? userMechanismApplicable(termInfo(term), data, why_not) : true;
  }
}

/// The drive segments' cells at the two resolutions (file comment of extensions.h) and their evaluations at the
/// base brush parameters, per (preset, orientation).
struct DriveCells {
  struct Share {
    int cell;
    double time_s, distance_m;
  };
  std::vector<DiagnosisRun> fine, coarse;  ///< centroids (temperature in tread_temperature_c)
  std::vector<int> coarse_of_fine;
  std::vector<std::vector<Share>> fine_shares, coarse_shares;  ///< per run; empty for a steady run
  /// Keyed by preset, orientation and the tire file's friction and wear levels (the models of one data set share a
  /// tire file; the levels keep a model of another file from reading these).
  std::map<std::vector<double>, std::vector<ExtendedModel::RawResult>> fine_base, coarse_base;
  /// adhesion_wear's shear work E_a [J/m] per fine and coarse cell at the base brush parameters, per orientation.
  std::map<int, std::vector<double>> fine_adhesion, coarse_adhesion;
};

namespace {

/// Resolution of the coarse drive cells (extensions.h; the default widths: point_cells.h). On the WLTC drive of
/// test_drive_integration the fine cells carried by these at 0.8 times the friction are within 0.6% of the replay.
const PointCellParams kCoarseDriveCells{{100.0, 0.08}, {1e-3, 0.2}, {1e-3, 0.2}, {1.0, 0.6}, {1e-3, 0.6}, 3.0};

DiagnosisRun cellRun(const WeightedOperatingPoint& p) {
  DiagnosisRun c;
  c.op = p.op;
  c.op.tread_temperature_c = kNaN;
  c.tread_temperature_c = p.op.tread_temperature_c;
  return c;
}

/// Fine cells from the runs' points, coarse cells from the fine cells' centroids (with their weights, so both
/// keep the points' integrals and first moments), and each run's shares of both.
std::shared_ptr<DriveCells> buildDriveCells(const DiagnosisData& data) {
  auto cells = std::make_shared<DriveCells>();
  PointCells fine, coarse(kCoarseDriveCells);
  cells->fine_shares.resize(data.runs.size());
  cells->coarse_shares.resize(data.runs.size());
  for (std::size_t i = 0; i < data.runs.size(); ++i)
    for (const WeightedOperatingPoint& p : data.runs[i].drive_points) {
      const int c = fine.add(p);
      if (c >= 0) cells->fine_shares[i].push_back({c, p.time_s, p.distance_m});
    }
  for (const WeightedOperatingPoint& p : fine.points()) {
    cells->fine.push_back(cellRun(p));
    cells->coarse_of_fine.push_back(coarse.add(p));
  }
  for (const WeightedOperatingPoint& p : coarse.points()) cells->coarse.push_back(cellRun(p));
  for (std::size_t i = 0; i < data.runs.size(); ++i) {
    std::map<int, DriveCells::Share> merged;
    for (const DriveCells::Share& s : cells->fine_shares[i]) {
      const int c = cells->coarse_of_fine[static_cast<std::size_t>(s.cell)];
      DriveCells::Share& m = merged.emplace(c, DriveCells::Share{c, 0.0, 0.0}).first->second;
      m.time_s += s.time_s;
      m.distance_m += s.distance_m;
    }
    for (const auto& [c, share] : merged) cells->coarse_shares[i].push_back(share);
  }
  return cells;
}

/// contact_time_wear's 4ab/V [m s] at a point (Eq 19's w4 term per distance); 0 at standstill.
double contactAreaPerSpeed(const FootprintParams& footprint, const OperatingPoint& op) {
  if (!(op.speed_mps > 0.0) || !(op.load_n > 0.0)) return 0.0;
  return 4.0 * footprint.halfLength(op.load_n) * footprint.b_m / op.speed_mps;
}

/// adhesion_wear's E_a [J/m] at each point, at the tire file's brush parameters (adhesion_wear.h).
std::vector<double> adhesionWork(const TireParams& base, TurnSlipOrientation orientation,
                                 const std::vector<const DiagnosisRun*>& points) {
  TireParams unit = base;
  unit.wear.adhesion_kg_per_j = 1.0;  // evaluate() returns zeros when the coefficient is 0
  const AdhesionWear adhesion(unit);
  std::vector<double> work(points.size(), 0.0);
  for (std::size_t j = 0; j < points.size(); ++j) {
    const OperatingPoint& op = points[j]->op;
    if (!(op.load_n > 0.0) || !(op.speed_mps > 0.0)) continue;
    const ContactPatch patch(base.footprint, op.load_n);
    work[j] = adhesion.evaluate(op, patch, op.tipKinematics(orientation), op.rollingSpeed()).work_j_per_m;
  }
  return work;
}

/// adhesionWork of the drive cells, cached per orientation in `store` (DriveCells::fine_adhesion, coarse_adhesion).
const std::vector<double>& cellAdhesionWork(const TireParams& base, TurnSlipOrientation orientation,
                                            const std::vector<DiagnosisRun>& cells,
                                            std::map<int, std::vector<double>>* store) {
  const int key = static_cast<int>(orientation);
  auto it = store->find(key);
  if (it == store->end()) {
    std::vector<const DiagnosisRun*> points;
    for (const DiagnosisRun& c : cells) points.push_back(&c);
    it = store->emplace(key, adhesionWork(base, orientation, points)).first;
  }
  return it->second;
}

/// Steady runs with this key share one brush evaluation (repeats of a condition).
std::array<double, 6> steadyKey(const DiagnosisRun& r) {
  return {r.op.speed_mps, r.op.slip_angle_rad, r.op.slip_ratio, r.op.path_curvature_per_m, r.op.load_n,
          std::isfinite(r.load_std_n) ? r.load_std_n : 0.0};
}

}  // namespace

ExtendedModel::ExtendedModel(const TireParams& base, const ExtendedModelOptions& options, std::vector<Term> terms,
                             const DiagnosisData& data)
    : base_(base), options_(options), terms_(std::move(terms)), data_(data) {
  std::string error;
  if (!base_.validate(&error)) throw std::invalid_argument(error);
  offsets_.assign(termLibrary().size(), -1);
  num_parameters_ = kBaseParameters;
  for (Term t : terms_) {
    const TermInfo& info = termInfo(t);
    if (offsets_[static_cast<int>(t)] >= 0) throw std::invalid_argument("term listed twice: " + info.name);
    offsets_[static_cast<int>(t)] = num_parameters_;
    if (info.user) user_terms_.emplace_back(num_parameters_, std::make_shared<MechanismEvaluator>(info, data_));
    num_parameters_ += static_cast<int>(termInfo(t).parameters.size());
  }
  TurnSlipOrientation orientation = options_.orientation;
  if (has(Term::kTurnSlipOrientation))
    orientation = orientation == TurnSlipOrientation::kLiteral ? TurnSlipOrientation::kFlipped
                                                               : TurnSlipOrientation::kLiteral;
  brush_options_ = presetOptions(options_.preset, orientation);

  std::set<std::array<double, 6>> steady;
  bool any_drive = false;
  for (const DiagnosisRun& r : data_.runs) {
    if (r.isDrive()) any_drive = true;
    else steady.insert(steadyKey(r));
  }
  distinct_steady_ = steady.size();
  if (any_drive) {
    if (!data_.drive_cells) data_.drive_cells = buildDriveCells(data_);
    drive_ = data_.drive_cells;
  }
}

std::size_t ExtendedModel::fineDriveCells() const { return drive_ ? drive_->fine.size() : 0; }

std::size_t ExtendedModel::evaluationPoints() const {
  return distinct_steady_ + (drive_ ? drive_->coarse.size() : 0);
}

int ExtendedModel::parameterOffset(Term term) const { return offsets_[static_cast<int>(term)]; }

std::vector<FitParameter> ExtendedModel::parameters() const {
  std::vector<FitParameter> p;
  p.push_back({"w3_scale", 1.0, 0.05, 20.0, true});
  p.push_back({"mu_scale", 1.0, 0.3, 3.0, true});
  double t_lo = INFINITY, t_hi = -INFINITY;
  for (const DiagnosisRun& r : data_.runs)
    if (std::isfinite(r.tread_temperature_c)) {
      t_lo = std::min(t_lo, r.tread_temperature_c);
      t_hi = std::max(t_hi, r.tread_temperature_c);
    }
  for (Term t : terms_) {
    for (const TermParameterSpec& s : termInfo(t).parameters) {
      FitParameter f{s.name, s.initial, s.lower, s.upper, s.log_scale};
      if (t == Term::kThermalWear && std::isfinite(t_lo)) {
        // Start from the file's Eq 25 when it is on; else at the coolest run with a width of the observed span.
        const double span = std::max(t_hi - t_lo, 5.0);
        if (s.name == "t0_c") {
          f.initial = base_.wear.temperature_enabled ? base_.wear.t0_c : t_lo;
          f.lower = t_lo - 3.0 * span;
          f.upper = t_hi + 3.0 * span;
          f.initial = std::clamp(f.initial, f.lower, f.upper);
        } else {
          f.initial = base_.wear.temperature_enabled ? base_.wear.sigma_t_c : span;
        }
      }
      if (t == Term::kPressureFriction) f.initial = base_.friction.q;
      p.push_back(f);
    }
  }
  return p;
}

std::vector<std::vector<FitParameter>> ExtendedModel::fitStarts(const std::vector<FitParameter>& params,
                                                                bool t0_given) const {
  const int tw = parameterOffset(Term::kThermalWear);
  if (tw < 0 || t0_given) return {params};
  double lo = INFINITY, hi = -INFINITY;
  for (const DiagnosisRun& r : data_.runs) {
    lo = std::min(lo, r.tread_temperature_c);
    hi = std::max(hi, r.tread_temperature_c);
  }
  const double span = std::max(hi - lo, 5.0);
  std::vector<std::vector<FitParameter>> starts;
  for (double t0 : {lo - 0.5 * span, 0.5 * (lo + hi), hi + 0.5 * span}) {
    std::vector<FitParameter> s = params;
    s[tw].initial = std::clamp(t0, s[tw].lower, s[tw].upper);
    s[tw + 1].initial = span;
    starts.push_back(s);
  }
  return starts;
}

ExtendedModel::RawResult ExtendedModel::evaluateRun(const BrushWearModel& model, const DiagnosisRun& run,
                                                    double compliance, double load_std_scale) const {
  const TireParams& tp = model.params();
  auto at = [&](double load_n) {
    OperatingPoint op = run.op;
    op.load_n = load_n;
    WearResult r;
    if (compliance > 0.0) {
      // Secant iteration on g(a) = a - alpha - c Fy(a); the first step is the fixed-point step.
      const double alpha = run.op.slip_angle_rad;
      double a0 = alpha;
      model.evaluate(op, &r);
      double g0 = -compliance * r.fy_n;
      double a1 = std::clamp(alpha + compliance * r.fy_n, -1.5, 1.5);
      for (int it = 0; it < kComplianceIterations; ++it) {
        op.slip_angle_rad = a1;
        model.evaluate(op, &r);
        const double g1 = a1 - alpha - compliance * r.fy_n;
        if (std::abs(g1) < kComplianceTolerance_rad || g1 == g0) break;
        const double a2 = std::clamp(a1 - g1 * (a1 - a0) / (g1 - g0), -1.5, 1.5);
        a0 = a1;
        g0 = g1;
        a1 = a2;
      }
    } else {
      model.evaluate(op, &r);
    }
    // w4 acts on the whole patch: its part of W_r is w4 4ab / V (Eqs 19-20).
    const double a = tp.footprint.halfLength(load_n);
    const double w4_part = tp.wear.w4_kg_per_s_m2 * 4.0 * a * tp.footprint.b_m / run.op.speed_mps;
    return RawResult{r.fy_n, r.wear_rate_kg_per_m - w4_part, w4_part};
  };
  const double sd = std::isfinite(run.load_std_n) ? load_std_scale * run.load_std_n : 0.0;
  if (!(sd > 0.0)) return at(run.op.load_n);
  // Eq 23 over N(Fz, sd^2) with 3-point Gauss-Hermite; the spread is capped so that every node load stays > 0.
  const double spread = std::min(std::sqrt(3.0) * sd, 0.9 * run.op.load_n);
  const RawResult lo = at(run.op.load_n - spread), mid = at(run.op.load_n), hi = at(run.op.load_n + spread);
  auto avg = [](double l, double m, double h) { return (l + h) / 6.0 + 2.0 * m / 3.0; };
  return RawResult{avg(lo.fy_n, mid.fy_n, hi.fy_n),
                   avg(lo.wear_w3_kg_per_m, mid.wear_w3_kg_per_m, hi.wear_w3_kg_per_m),
                   avg(lo.wear_w4_kg_per_m, mid.wear_w4_kg_per_m, hi.wear_w4_kg_per_m)};
}

bool ExtendedModel::predict(const std::vector<double>& values, Prediction* out) const {
  if (static_cast<int>(values.size()) != num_parameters_) return false;
  for (double v : values)
    if (!std::isfinite(v)) return false;
  const double w3_scale = values[0], mu_scale = values[1];
  auto value = [&](Term t, int k) { return values[parameterOffset(t) + k]; };
  const double k_t = has(Term::kThermalFriction) ? value(Term::kThermalFriction, 0) : 0.0;
  const double compliance = has(Term::kLateralCompliance) ? value(Term::kLateralCompliance, 0) : 0.0;
  const double q = has(Term::kPressureFriction) ? value(Term::kPressureFriction, 0) : base_.friction.q;
  const double load_std_scale = has(Term::kLoadFluctuation) ? value(Term::kLoadFluctuation, 0) : 0.0;
  const std::vector<double> key = {mu_scale, k_t, compliance, q, load_std_scale};
  const bool at_base = mu_scale == 1.0 && k_t == 0.0 && compliance == 0.0 && q == base_.friction.q;
  const int n = static_cast<int>(data_.runs.size());
  const std::vector<DiagnosisRun> no_cells;
  const std::vector<DiagnosisRun>& coarse = drive_ ? drive_->coarse : no_cells;
  const int n_coarse = static_cast<int>(coarse.size());

  // The brush model at these values for the runs in `points` (run j of `points`, or steady run j of the data).
  TireParams p = base_;
  p.friction.mu_0 *= mu_scale;
  p.friction.mu_m *= mu_scale;
  p.friction.q = q;
  p.wear.temperature_enabled = false;  // Eq 25 is applied below, after the brush evaluation
  auto evaluate = [&](const std::vector<const DiagnosisRun*>& points, std::vector<RawResult>* raw) {
    if (k_t != 0.0) {
      // One brush model per tread temperature, to kThermalFrictionResolution_c: drive cells share them (a cell's
      // friction factor is then off by at most k_T x 0.05 degC, below 1e-4 for any plausible k_T).
      const double t_ref = termInfo(Term::kThermalFriction).temperature_ref_c;
      std::map<long, std::unique_ptr<BrushWearModel>> models;
      for (std::size_t j = 0; j < points.size(); ++j) {
        if (points[j] == nullptr) continue;
        if (!std::isfinite(points[j]->tread_temperature_c)) return false;  // the term needs the temperature
        const long t_key = std::lround(points[j]->tread_temperature_c / kThermalFrictionResolution_c);
        auto it = models.find(t_key);
        if (it == models.end()) {
          const double factor = 1.0 - k_t * (t_key * kThermalFrictionResolution_c - t_ref);
          if (!(factor > 0.05)) return false;  // friction would vanish: outside the term's validity
          TireParams pj = p;
          pj.friction.mu_0 *= factor;
          pj.friction.mu_m *= factor;
          it = models.emplace(t_key, std::make_unique<BrushWearModel>(pj, brush_options_)).first;
        }
        (*raw)[j] = evaluateRun(*it->second, *points[j], compliance, load_std_scale);
      }
      return true;
    }
    const BrushWearModel model(p, brush_options_);
    // Repeats of a condition share one evaluation.
    std::map<std::array<double, 6>, RawResult> seen;
    for (std::size_t j = 0; j < points.size(); ++j) {
      if (points[j] == nullptr) continue;
      auto it = seen.find(steadyKey(*points[j]));
      if (it == seen.end())
        it = seen.emplace(steadyKey(*points[j]), evaluateRun(model, *points[j], compliance, load_std_scale)).first;
      (*raw)[j] = it->second;
    }
    return true;
  };

  // Raw brush results of the steady runs (0..n-1; unused for drive segments) and the coarse cells (n..).
  auto found = cache_.find(key);
  if (found == cache_.end()) {
    std::vector<const DiagnosisRun*> points(n + n_coarse, nullptr);
    for (int i = 0; i < n; ++i)
      if (!data_.runs[i].isDrive()) points[i] = &data_.runs[i];
    for (int c = 0; c < n_coarse; ++c) points[n + c] = &coarse[c];
    std::vector<RawResult> raw(points.size());
    try {
      if (!evaluate(points, &raw)) return false;
    } catch (const std::exception&) {
      return false;
    }
    brush_evaluations_ += static_cast<long>(evaluationPoints());
    if (cache_.size() >= kCacheEntries) cache_.clear();
    found = cache_.emplace(key, std::move(raw)).first;
  }
  const std::vector<RawResult>& raw = found->second;

  // The drive cells' results: the coarse ones as they are, or the fine ones at the base values carried to these
  // values by the coarse ones' change (extensions.h).
  std::vector<RawResult> fine;
  if (drive_ && !options_.coarse_drive_cells) {
    const std::vector<double> preset_key = {static_cast<double>(options_.preset),
                                            static_cast<double>(brush_options_.orientation),
                                            base_.friction.mu_0,
                                            base_.friction.mu_m,
                                            base_.friction.q,
                                            base_.wear.w3_kg_per_s_m2,
                                            base_.wear.w4_kg_per_s_m2,
                                            base_.footprint.b_m};
    auto base_results = [&](const std::vector<DiagnosisRun>& cells,
                            std::map<std::vector<double>, std::vector<RawResult>>* store) -> const std::vector<RawResult>& {
      auto it = store->find(preset_key);
      if (it == store->end()) {
        std::vector<RawResult> r(cells.size());
        const BrushWearModel model([&] {
          TireParams b = base_;
          b.wear.temperature_enabled = false;
          return b;
        }(), brush_options_);
        for (std::size_t c = 0; c < cells.size(); ++c) r[c] = evaluateRun(model, cells[c], 0.0, 0.0);
        it = store->emplace(preset_key, std::move(r)).first;
      }
      return it->second;
    };
    try {
      fine = base_results(drive_->fine, &drive_->fine_base);
      if (!at_base) {
        const std::vector<RawResult>& coarse_base = base_results(coarse, &drive_->coarse_base);
        for (std::size_t c = 0; c < fine.size(); ++c) {
          const int m = drive_->coarse_of_fine[c];
          const RawResult& now = raw[n + m];
          const RawResult& then = coarse_base[m];
          fine[c].fy_n += now.fy_n - then.fy_n;
          fine[c].wear_w3_kg_per_m = then.wear_w3_kg_per_m > 0.0
                                         ? fine[c].wear_w3_kg_per_m * now.wear_w3_kg_per_m / then.wear_w3_kg_per_m
                                         : now.wear_w3_kg_per_m;
        }
      }
    } catch (const std::exception&) {
      return false;
    }
  }
  const bool use_fine = !fine.empty();
  const std::vector<DiagnosisRun>& cells = use_fine ? drive_->fine : coarse;
  auto cell_result = [&](int c) -> const RawResult& { return use_fine ? fine[c] : raw[n + c]; };
  // The w3 factor of Eq 25 (or the thermal_wear term) at a tread temperature.
  auto thermal_w3 = [&](double temperature_c) {
    if (has(Term::kThermalWear)) {
      const double d = temperature_c - value(Term::kThermalWear, 0);
      const double s = value(Term::kThermalWear, 1);
      return std::exp(d * d / (2.0 * s * s));
    }
    return base_.wear.temperature_enabled ? base_.wear.temperatureFactor(temperature_c) : 1.0;
  };
  // The road wear terms (contact_time_wear, adhesion_wear): additive per distance, no brush re-evaluation.
  const double w4_extra = has(Term::kContactTimeWear) ? value(Term::kContactTimeWear, 0) : 0.0;
  const double k_a = has(Term::kAdhesionWear) ? value(Term::kAdhesionWear, 0) : 0.0;
  const std::vector<double>* cell_work =
      has(Term::kAdhesionWear) && drive_
          ? &cellAdhesionWork(base_, brush_options_.orientation, cells,
                              use_fine ? &drive_->fine_adhesion : &drive_->coarse_adhesion)
          : nullptr;
  auto road_terms = [&](const DiagnosisRun& point, double work_j_per_m) {
    return w4_extra * contactAreaPerSpeed(base_.footprint, point.op) + k_a * work_j_per_m;
  };
  out->side_force_n.resize(n);
  out->wear_kg_per_m.resize(n);
  for (int i = 0; i < n; ++i) {
    const DiagnosisRun& r = data_.runs[i];
    double fy = raw[i].fy_n;
    double w3_factor = w3_scale;
    if (has(Term::kSurfacePolishing))
      w3_factor *= std::exp(-value(Term::kSurfacePolishing, 0) * r.cumulative_sliding_m / 1000.0);
    double wear = 0.0;
    if (r.isDrive()) {
      double fy_sum = 0.0, wear_sum = 0.0;
      for (const DriveCells::Share& s : use_fine ? drive_->fine_shares[i] : drive_->coarse_shares[i]) {
        const RawResult& c = cell_result(s.cell);
        fy_sum += c.fy_n * s.time_s;
        wear_sum += (w3_factor * thermal_w3(cells[s.cell].tread_temperature_c) * c.wear_w3_kg_per_m +
                     c.wear_w4_kg_per_m + road_terms(cells[s.cell], cell_work ? (*cell_work)[s.cell] : 0.0)) *
                    s.distance_m;
      }
      fy = fy_sum / r.drive_time_s;
      wear = wear_sum / r.drive_distance_m;
    } else {
      wear = w3_factor * thermal_w3(r.tread_temperature_c) * raw[i].wear_w3_kg_per_m + raw[i].wear_w4_kg_per_m;
      if (w4_extra != 0.0 || k_a != 0.0)
        wear += road_terms(r, k_a != 0.0 ? adhesionWork(base_, brush_options_.orientation, {&r}).front() : 0.0);
    }
    if (has(Term::kSensorGain)) fy *= value(Term::kSensorGain, 0);
    if (has(Term::kSensorOffset)) fy += value(Term::kSensorOffset, 0);
    for (const auto& [offset, evaluator] : user_terms_) evaluator->apply(i, &values[offset], &fy, &wear);
    out->side_force_n[i] = fy;
    out->wear_kg_per_m[i] = wear;
    if (!std::isfinite(out->side_force_n[i]) || !std::isfinite(out->wear_kg_per_m[i])) return false;
  }
  return true;
}

}  // namespace diagnosis
}  // namespace tread_wear
