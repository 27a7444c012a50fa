#include "tread_wear/diagnosis/extensions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>

#include "tread_wear/diagnosis/parallel_for.h"
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
/// Compliance root: |alpha_eff - alpha - c Fy| below this [rad] ends the secant iteration. Measured on drive cells
/// against 1e-13: W_r within 7e-7 (relative) at 2e-5 to 3e-3 rad/N, 3.2-3.5 brush evaluations a cell.
constexpr double kComplianceTolerance_rad = 1e-8;
/// thermal_friction evaluates one brush model per tread temperature rounded to this [degC].
constexpr double kThermalFrictionResolution_c = 0.1;
constexpr int kComplianceIterations = 12;

std::vector<TermInfo> makeLibrary() {
  std::vector<TermInfo> lib;
  lib.push_back(
      {Term::kThermalWear,
       "thermal_wear",
       "abrasion resistance depends on the tread temperature: w3 -> w3 exp((T - T0)^2 / (2 sigma_T^2)) "
       "(Eq 25)",
       true,
       {false, true},
       {{"t0_c", 40.0, -50.0, 200.0, false, kNaN, "degC"}, {"sigma_t_c", 30.0, 2.0, 1000.0, true, kNaN, "degC"}},
       1});
  lib.push_back({Term::kThermalFriction,
                 "thermal_friction",
                 "rubber friction falls as the tread warms: mu_0, mu_m -> (1 - k_T (T - 23 degC)) mu_0, mu_m",
                 true,
                 {true, true},
                 {{"k_t_per_k", 0.0, -0.015, 0.015, false, 0.0, "1/K"}},
                 0});
  lib.push_back({Term::kSurfacePolishing,
                 "surface_polishing",
                 "the track gets polished: abrasiveness decays as exp(-r_p L) with the sliding distance L on the "
                 "current surface, reset when the surface is renewed (each cycle)",
                 true,
                 {false, true},
                 {{"polishing_rate_per_km", 0.2, 0.0, 10.0, false, 0.0, "1/km"}},
                 0});
  // lateral_compliance starts from no effect: the slip falls as alpha / (1 + c C_alpha), concave in c, and from
  // below Gauss-Newton steps approach the fit without overshooting (from 1e-4 rad/N, c C_alpha about 7, a fit on 12
  // drives took 34 iterations back to 0, each re-simulating every coarse cell).
  lib.push_back({Term::kLateralCompliance,
                 "lateral_compliance",
                 "the wheel or carcass bends under the side force, lowering the effective slip angle: "
                 "|alpha_eff| = |alpha| - c_lat |Fy|",
                 true,
                 {true, true},
                 {{"compliance_rad_per_n", 0.0, 0.0, 3e-3, false, 0.0, "rad/N"}},
                 0});
  lib.push_back({Term::kPressureFriction,
                 "pressure_friction",
                 "friction falls with contact pressure more (or less) than the file says: the sat(p) exponent q "
                 "of Eq 11 is free",
                 true,
                 {true, true},
                 {{"q", 0.14, 0.0, 1.0, false, 0.14, "-"}},
                 0});
  lib.push_back({Term::kLoadFluctuation,
                 "load_fluctuation",
                 "the vertical load fluctuates during a run: forces and wear are the Eq 23 average over "
                 "N(Fz, (s_load load_std)^2) instead of the value at the mean load",
                 true,
                 {true, true},
                 {{"load_std_scale", 1.0, 0.0, 6.0, false, 0.0, "-"}},
                 0});
  lib.push_back({Term::kTurnSlipOrientation,
                 "turn_slip_orientation",
                 "the slip angle is oriented the other way against the track curve (turn slip adds to sideslip "
                 "instead of opposing it)",
                 true,
                 {true, true},
                 {},
                 -1});
  lib.push_back({Term::kSensorGain,
                 "sensor_gain",
                 "not physics: the side-force transducer reads g times the true force (calibration gain error)",
                 false,
                 {true, false},
                 {{"side_force_gain", 1.0, 0.5, 1.5, false, 1.0, "-"}},
                 0});
  lib.push_back({Term::kSensorOffset,
                 "sensor_offset",
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

/// The coarse cells at a node of the friction factor (ExtendedModelOptions::interpolate_mu_scale): each cell is
/// evaluated when an interpolation first needs it there, and kept for the whole diagnosis.
struct DriveNodeColumn {
  std::vector<ExtendedModel::RawResult> result;  ///< per coarse cell
  std::vector<char> done;                        ///< whether result[c] has been evaluated
};

/// Per drive cell factors of the wear that do not depend on the fitted parameters.
struct DriveCellFactors {
  std::vector<double> area_per_speed_m_s;  ///< contact_time_wear's 4ab/V [m s]
  std::vector<double> file_thermal;        ///< the tire file's Eq 25 factor at the cell's temperature [-]
};

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
  /// Brush results of the steady runs and the coarse cells per (preset key, brush parameters), shared by every
  /// model of the data (ExtendedModel::rawResults); guarded with the stores above by raw_cache_lock.
  std::map<std::vector<double>, std::vector<ExtendedModel::RawResult>> raw_cache;
  std::map<std::vector<double>, DriveNodeColumn> node_cache;  ///< by preset key and node index
  /// By resolution and the tire file's footprint and Eq 25 (ExtendedModel::cellFactors).
  std::map<std::vector<double>, DriveCellFactors> factors;
  std::mutex raw_cache_lock;
};

namespace {

/// Resolution of the coarse drive cells (extensions.h; the default widths: point_cells.h). On the WLTC drive of
/// test_drive_integration the fine cells carried by these at 0.8 times the friction are within 0.6% of the replay.
const PointCellParams kCoarseCells{{100.0, 0.08}, {1e-3, 0.2}, {1e-3, 0.2}, {1.0, 0.6}, {1e-3, 0.6}, 3.0};

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
  PointCells fine, coarse(kCoarseCells);
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
  return {r.op.speed_mps,  r.op.slip_angle_rad,
          r.op.slip_ratio, r.op.path_curvature_per_m,
          r.op.load_n,     std::isfinite(r.load_std_n) ? r.load_std_n : 0.0};
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
    orientation =
        orientation == TurnSlipOrientation::kLiteral ? TurnSlipOrientation::kFlipped : TurnSlipOrientation::kLiteral;
  brush_options_ = presetOptions(options_.preset, orientation);

  std::set<std::array<double, 6>> steady;
  bool any_drive = false;
  for (const DiagnosisRun& r : data_.runs) {
    if (r.isDrive())
      any_drive = true;
    else
      steady.insert(steadyKey(r));
  }
  distinct_steady_ = steady.size();
  if (any_drive) {
    if (!data_.drive_cells) data_.drive_cells = buildDriveCells(data_);
    drive_ = data_.drive_cells;
  }
}

std::size_t ExtendedModel::fineDriveCells() const { return drive_ ? drive_->fine.size() : 0; }

std::size_t ExtendedModel::evaluationPoints() const { return distinct_steady_ + (drive_ ? drive_->coarse.size() : 0); }

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

namespace {

/// The brush model at the effective slip angle of lateral_compliance: the root of g(a) = a - alpha - c Fy(a), by
/// secant steps from alpha and a first step that is exact for a linear tire, Fy(a) = Fy(alpha) a / alpha (the
/// fixed-point step alpha + c Fy(alpha) overshoots by the factor c |dFy/dalpha|, 7 on a passenger tire at 1e-4
/// rad/N, and could end on the saturated flank). g' = 1 - c dFy/da >= 1 wherever Fy falls with a, so the root there
/// is unique.
void complianceSolve(const BrushWearModel& model, OperatingPoint op, double compliance, WearResult* r) {
  const double alpha = op.slip_angle_rad;
  model.evaluate(op, r);
  double a0 = alpha, g0 = -compliance * r->fy_n;
  const double linear = 1.0 - compliance * r->fy_n / alpha;  // > 1 where Fy opposes alpha
  double a1 = alpha != 0.0 && linear > 1.0 ? alpha / linear : std::clamp(alpha + compliance * r->fy_n, -1.5, 1.5);
  for (int it = 0; it < kComplianceIterations; ++it) {
    op.slip_angle_rad = a1;
    model.evaluate(op, r);
    const double g1 = a1 - alpha - compliance * r->fy_n;
    if (std::abs(g1) < kComplianceTolerance_rad || g1 == g0) break;
    const double a2 = std::clamp(a1 - g1 * (a1 - a0) / (g1 - g0), -1.5, 1.5);
    a0 = a1;
    g0 = g1;
    a1 = a2;
  }
}

}  // namespace

ExtendedModel::RawResult ExtendedModel::evaluateRun(const BrushWearModel& model, const DiagnosisRun& run,
                                                    double compliance, double load_std_scale) const {
  const TireParams& tp = model.params();
  auto at = [&](double load_n) {
    OperatingPoint op = run.op;
    op.load_n = load_n;
    WearResult r;
    if (compliance > 0.0)
      complianceSolve(model, op, compliance, &r);
    else
      model.evaluate(op, &r);
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
  return RawResult{avg(lo.fy_n, mid.fy_n, hi.fy_n), avg(lo.wear_w3_kg_per_m, mid.wear_w3_kg_per_m, hi.wear_w3_kg_per_m),
                   avg(lo.wear_w4_kg_per_m, mid.wear_w4_kg_per_m, hi.wear_w4_kg_per_m)};
}

ExtendedModel::BrushSetting ExtendedModel::brushSetting(const std::vector<double>& values) const {
  auto value = [&](Term t, double otherwise) { return has(t) ? values[parameterOffset(t)] : otherwise; };
  return BrushSetting{values[1], value(Term::kThermalFriction, 0.0), value(Term::kLateralCompliance, 0.0),
                      value(Term::kPressureFriction, base_.friction.q), value(Term::kLoadFluctuation, 0.0)};
}

bool ExtendedModel::evaluatePoints(const BrushSetting& s, const std::vector<const DiagnosisRun*>& points,
                                   std::vector<RawResult>* raw) const {
  TireParams p = base_;
  p.friction.mu_0 *= s.mu_scale;
  p.friction.mu_m *= s.mu_scale;
  p.friction.q = s.q;
  p.wear.temperature_enabled = false;  // Eq 25 is applied after the brush evaluation
  // Each point's brush model: one per tread temperature with thermal_friction, else one for all. The models are
  // built here, serially; the evaluations below run in parallel and write only their own slots.
  std::vector<const BrushWearModel*> model_of(points.size(), nullptr);
  std::map<long, std::unique_ptr<BrushWearModel>> models;
  if (s.k_t != 0.0) {
    // One brush model per tread temperature, to kThermalFrictionResolution_c: drive cells share them (a cell's
    // friction factor is then off by at most k_T x 0.05 degC, below 1e-4 for any plausible k_T).
    const double t_ref = termInfo(Term::kThermalFriction).temperature_ref_c;
    for (std::size_t j = 0; j < points.size(); ++j) {
      if (points[j] == nullptr) continue;
      if (!std::isfinite(points[j]->tread_temperature_c)) return false;  // the term needs the temperature
      const long t_key = std::lround(points[j]->tread_temperature_c / kThermalFrictionResolution_c);
      auto it = models.find(t_key);
      if (it == models.end()) {
        const double factor = 1.0 - s.k_t * (t_key * kThermalFrictionResolution_c - t_ref);
        if (!(factor > 0.05)) return false;  // friction would vanish: outside the term's validity
        TireParams pj = p;
        pj.friction.mu_0 *= factor;
        pj.friction.mu_m *= factor;
        it = models.emplace(t_key, std::make_unique<BrushWearModel>(pj, brush_options_)).first;
      }
      model_of[j] = it->second.get();
    }
  } else {
    const BrushWearModel* shared =
        models.emplace(0, std::make_unique<BrushWearModel>(p, brush_options_)).first->second.get();
    for (std::size_t j = 0; j < points.size(); ++j)
      if (points[j] != nullptr) model_of[j] = shared;
  }
  // Repeats of a condition under one model share one evaluation: the first of them computes it.
  std::vector<std::size_t> first_of(points.size());
  std::vector<std::size_t> unique;
  std::map<std::pair<const BrushWearModel*, std::array<double, 6>>, std::size_t> seen;
  for (std::size_t j = 0; j < points.size(); ++j) {
    if (points[j] == nullptr) continue;
    const auto it = seen.emplace(std::make_pair(model_of[j], steadyKey(*points[j])), j).first;
    first_of[j] = it->second;
    if (it->second == j) unique.push_back(j);
  }
  parallelFor(unique.size(), options_.jobs, [&](std::size_t u) {
    const std::size_t j = unique[u];
    (*raw)[j] = evaluateRun(*model_of[j], *points[j], s.compliance, s.load_std_scale);
  });
  for (std::size_t j = 0; j < points.size(); ++j)
    if (points[j] != nullptr) (*raw)[j] = (*raw)[first_of[j]];
  cellsEvaluated() += static_cast<long>(unique.size());
  return true;
}

double ExtendedModel::w3Factor(const std::vector<double>& values, const DiagnosisRun& run) const {
  double f = values[0];
  if (has(Term::kSurfacePolishing))
    f *= std::exp(-values[parameterOffset(Term::kSurfacePolishing)] * run.cumulative_sliding_m / 1000.0);
  return f;
}

double ExtendedModel::thermalW3(const std::vector<double>& values, double temperature_c) const {
  if (has(Term::kThermalWear)) {
    const double d = temperature_c - values[parameterOffset(Term::kThermalWear)];
    const double s = values[parameterOffset(Term::kThermalWear) + 1];
    return std::exp(d * d / (2.0 * s * s));
  }
  return base_.wear.temperature_enabled ? base_.wear.temperatureFactor(temperature_c) : 1.0;
}

std::size_t ExtendedModel::coarseCellCount() const { return drive_ ? drive_->coarse.size() : 0; }

bool ExtendedModel::coarseCellContributions(const std::vector<double>& values, const std::vector<int>& cells,
                                            std::vector<std::vector<CellContribution>>* out) const {
  if (!options_.coarse_cells_only || !drive_)
    throw std::logic_error("coarseCellContributions needs drive segments and coarse_cells_only");
  if (static_cast<int>(values.size()) != num_parameters_) return false;
  std::vector<const DiagnosisRun*> points;
  for (int c : cells) points.push_back(&drive_->coarse.at(static_cast<std::size_t>(c)));
  std::vector<RawResult> raw(points.size());
  try {
    if (!evaluatePoints(brushSetting(values), points, &raw)) return false;
  } catch (const std::exception&) {
    return false;
  }
  std::map<int, std::size_t> slot;  // coarse cell -> position in `cells`
  for (std::size_t k = 0; k < cells.size(); ++k) slot.emplace(cells[k], k);
  out->assign(cells.size(), {});
  const double gain = has(Term::kSensorGain) ? values[parameterOffset(Term::kSensorGain)] : 1.0;
  for (std::size_t i = 0; i < data_.runs.size(); ++i) {
    const DiagnosisRun& r = data_.runs[i];
    if (!r.isDrive()) continue;
    const double w3_factor = w3Factor(values, r);
    for (const DriveCells::Share& s : drive_->coarse_shares[i]) {
      const auto found = slot.find(s.cell);
      if (found == slot.end()) continue;
      const RawResult& c = raw[found->second];
      const double temperature_c = drive_->coarse[static_cast<std::size_t>(s.cell)].tread_temperature_c;
      (*out)[found->second].push_back(
          {static_cast<int>(i), gain * c.fy_n * s.time_s / r.drive_time_s,
           (w3_factor * thermalW3(values, temperature_c) * c.wear_w3_kg_per_m + c.wear_w4_kg_per_m) * s.distance_m /
               r.drive_distance_m});
    }
  }
  return true;
}

const std::vector<ExtendedModel::RawResult>* ExtendedModel::rawResults(const std::vector<double>& values) const {
  const BrushSetting s = brushSetting(values);
  std::vector<double> key = {s.mu_scale, s.k_t, s.compliance, s.q, s.load_std_scale};
  // With drive segments the cache lives with the data's cells, so that every model of a diagnosis (each fit, each
  // fold, each check) shares it: a cell is evaluated once per preset, orientation and brush parameters.
  std::map<std::vector<double>, std::vector<RawResult>>& cache = drive_ ? drive_->raw_cache : cache_;
  std::unique_lock<std::mutex> lock;
  if (drive_) {
    lock = std::unique_lock<std::mutex>(drive_->raw_cache_lock);
    const std::vector<double> prefix = presetKey();
    key.insert(key.begin(), prefix.begin(), prefix.end());
  }
  auto found = cache.find(key);
  if (found != cache.end()) return &found->second;
  if (interpolates(s)) {
    lock = std::unique_lock<std::mutex>();  // the nodes take the lock themselves
    bool ok = true;
    std::vector<RawResult> raw = interpolatedResults(s, &ok);
    if (!ok) return nullptr;
    lock = std::unique_lock<std::mutex>(drive_->raw_cache_lock);
    if (cache.size() >= kCacheEntries) cache.clear();
    return &cache.emplace(key, std::move(raw)).first->second;
  }
  const std::vector<const DiagnosisRun*> points = brushPoints(true, true);
  std::vector<RawResult> raw(points.size());
  try {
    if (!evaluatePoints(s, points, &raw)) return nullptr;
  } catch (const std::exception&) {
    return nullptr;
  }
  brush_evaluations_ += static_cast<long>(evaluationPoints());
  if (cache.size() >= kCacheEntries) cache.clear();
  return &cache.emplace(key, std::move(raw)).first->second;
}

std::vector<const DiagnosisRun*> ExtendedModel::brushPoints(bool steady, bool coarse) const {
  const std::size_t n = data_.runs.size(), n_coarse = drive_ ? drive_->coarse.size() : 0;
  std::vector<const DiagnosisRun*> points(n + n_coarse, nullptr);
  for (std::size_t i = 0; steady && i < n; ++i)
    if (!data_.runs[i].isDrive()) points[i] = &data_.runs[i];
  for (std::size_t c = 0; coarse && c < n_coarse; ++c) points[n + c] = &drive_->coarse[c];
  return points;
}

bool ExtendedModel::interpolates(const BrushSetting& s) const {
  return drive_ && options_.interpolate_mu_scale && s.compliance == 0.0 && s.q == base_.friction.q &&
         s.load_std_scale == 0.0;
}

std::vector<ExtendedModel::RawResult> ExtendedModel::interpolatedResults(const BrushSetting& s, bool* ok) const {
  const std::size_t n = data_.runs.size(), n_coarse = drive_->coarse.size();
  std::vector<RawResult> raw(n + n_coarse);
  *ok = true;
  try {
    *ok = evaluatePoints(s, brushPoints(true, false), &raw);  // the steady runs as they are
  } catch (const std::exception&) {
    *ok = false;
  }
  // Each cell's place among the nodes: its friction factor (mu_scale, times thermal_friction's factor at the cell's
  // temperature) in ln, over the spacing.
  std::vector<double> x(n_coarse);
  const double t_ref = termInfo(Term::kThermalFriction).temperature_ref_c;
  for (std::size_t c = 0; *ok && c < n_coarse; ++c) {
    double factor = s.mu_scale;
    if (s.k_t != 0.0) {
      const double thermal = 1.0 - s.k_t * (drive_->coarse[c].tread_temperature_c - t_ref);
      if (!(thermal > 0.05)) *ok = false;  // friction would vanish (or no temperature): outside the term's validity
      factor *= thermal;
    }
    x[c] = std::log(factor) / kMuScaleNodeSpacing;
  }
  if (!*ok) return raw;
  std::map<long, std::vector<int>> cells_of_node;
  for (std::size_t c = 0; c < n_coarse; ++c) {
    const long j = static_cast<long>(std::floor(x[c]));
    for (long node = j - 1; node <= j + 2; ++node) cells_of_node[node].push_back(static_cast<int>(c));
  }
  std::map<long, const DriveNodeColumn*> columns;
  for (const auto& [node, cells] : cells_of_node) {
    columns[node] = nodeColumn(node, cells);
    if (columns[node] == nullptr) {
      *ok = false;
      return raw;
    }
  }
  // Catmull-Rom between the nodes j and j + 1 around x, with the nodes j - 1 and j + 2 for the slopes (C1 in
  // the friction factor, exact at the nodes: mu_scale 1 is node 0).
  for (std::size_t c = 0; c < n_coarse; ++c) {
    const double j = std::floor(x[c]), t = x[c] - j;
    const double weight[4] = {0.5 * (-t * t * t + 2 * t * t - t), 0.5 * (3 * t * t * t - 5 * t * t + 2),
                              0.5 * (-3 * t * t * t + 4 * t * t + t), 0.5 * (t * t * t - t * t)};
    RawResult& r = raw[n + c];
    r = RawResult{0.0, 0.0, 0.0};
    for (int k = 0; k < 4; ++k) {
      const RawResult& at = columns.at(static_cast<long>(j) - 1 + k)->result[c];
      r.fy_n += weight[k] * at.fy_n;
      r.wear_w3_kg_per_m += weight[k] * at.wear_w3_kg_per_m;
      r.wear_w4_kg_per_m += weight[k] * at.wear_w4_kg_per_m;
    }
  }
  return raw;
}

const DriveNodeColumn* ExtendedModel::nodeColumn(long node, const std::vector<int>& cells) const {
  std::vector<double> key = presetKey();
  key.push_back(static_cast<double>(node));
  std::vector<int> missing;
  DriveNodeColumn* column = nullptr;
  {
    std::lock_guard<std::mutex> lock(drive_->raw_cache_lock);
    column = &drive_->node_cache[key];
    column->result.resize(drive_->coarse.size());
    column->done.resize(drive_->coarse.size(), 0);
    for (int c : cells)
      if (!column->done[static_cast<std::size_t>(c)]) missing.push_back(c);
  }
  if (missing.empty()) return column;
  std::vector<const DiagnosisRun*> points;
  for (int c : missing) points.push_back(&drive_->coarse[static_cast<std::size_t>(c)]);
  std::vector<RawResult> raw(points.size());
  const BrushSetting at_node{std::exp(node * kMuScaleNodeSpacing), 0.0, 0.0, base_.friction.q, 0.0};
  try {
    if (!evaluatePoints(at_node, points, &raw)) return nullptr;
  } catch (const std::exception&) {
    return nullptr;
  }
  brush_evaluations_ += static_cast<long>(missing.size());
  std::lock_guard<std::mutex> lock(drive_->raw_cache_lock);
  for (std::size_t k = 0; k < missing.size(); ++k) {
    column->result[static_cast<std::size_t>(missing[k])] = raw[k];
    column->done[static_cast<std::size_t>(missing[k])] = 1;
  }
  return column;
}

std::vector<double> ExtendedModel::presetKey() const {
  return {static_cast<double>(options_.preset),
          options_.interpolate_mu_scale ? 1.0 : 0.0,
          static_cast<double>(brush_options_.orientation),
          base_.friction.mu_0,
          base_.friction.mu_m,
          base_.friction.q,
          base_.wear.w3_kg_per_s_m2,
          base_.wear.w4_kg_per_s_m2,
          base_.footprint.b_m};
}

/// The drive cells' results at one parameter vector, read cell by cell (ExtendedModel::predict): the coarse cells as
/// they are, or the fine cells at the base carried by their coarse cell's change.
struct DriveCellView {
  /// A coarse cell's change from the base brush parameters, which the fine cells inside it follow (extensions.h).
  struct CoarseChange {
    double fy_n;             ///< Fy now minus Fy at the base [N]
    double now_w3, base_w3;  ///< w3 part of W_r now and at the base [kg/m]
  };
  const std::vector<DiagnosisRun>* cells = nullptr;
  const std::vector<std::vector<DriveCells::Share>>* shares = nullptr;  ///< per run
  const ExtendedModel::RawResult* coarse = nullptr;                    ///< the coarse cells' results
  const std::vector<ExtendedModel::RawResult>* fine_base = nullptr;     ///< null: the coarse cells are read
  const std::vector<int>* coarse_of_fine = nullptr;
  std::vector<CoarseChange> change;                      ///< per coarse cell; empty at the base parameters
  const DriveCellFactors* factors = nullptr;             ///< per cell of `cells`
  std::vector<double> thermal;                           ///< Eq 25's factor per cell, with thermal_wear on
  const std::vector<double>* work = nullptr;             ///< adhesion_wear's E_a per cell [J/m]; null without it

  ExtendedModel::RawResult at(int c) const {
    if (fine_base == nullptr) return coarse[c];
    ExtendedModel::RawResult f = (*fine_base)[static_cast<std::size_t>(c)];
    if (change.empty()) return f;
    const CoarseChange& m = change[static_cast<std::size_t>((*coarse_of_fine)[static_cast<std::size_t>(c)])];
    f.fy_n += m.fy_n;
    f.wear_w3_kg_per_m = m.base_w3 > 0.0 ? f.wear_w3_kg_per_m * m.now_w3 / m.base_w3 : m.now_w3;
    return f;
  }
  double thermalFactor(int c) const {
    return thermal.empty() ? factors->file_thermal[static_cast<std::size_t>(c)] : thermal[static_cast<std::size_t>(c)];
  }
};

const std::vector<ExtendedModel::RawResult>& ExtendedModel::baseCellResults(bool fine) const {
  const std::vector<DiagnosisRun>& cells = fine ? drive_->fine : drive_->coarse;
  std::map<std::vector<double>, std::vector<RawResult>>& store = fine ? drive_->fine_base : drive_->coarse_base;
  const std::vector<double> preset_key = presetKey();
  std::lock_guard<std::mutex> lock(drive_->raw_cache_lock);
  auto it = store.find(preset_key);
  if (it == store.end()) {
    std::vector<RawResult> r(cells.size());
    TireParams b = base_;
    b.wear.temperature_enabled = false;
    const BrushWearModel model(b, brush_options_);
    parallelFor(cells.size(), options_.jobs, [&](std::size_t c) { r[c] = evaluateRun(model, cells[c], 0.0, 0.0); });
    cellsEvaluated() += static_cast<long>(cells.size());
    it = store.emplace(preset_key, std::move(r)).first;
  }
  return it->second;
}

const DriveCellFactors& ExtendedModel::cellFactors(bool fine) const {
  const std::vector<DiagnosisRun>& cells = fine ? drive_->fine : drive_->coarse;
  const FootprintParams& f = base_.footprint;
  const WearLawParams& w = base_.wear;
  const std::vector<double> key = {fine ? 1.0 : 0.0, f.a1_m, f.a2, f.a3_m, f.b_m,
                                   w.temperature_enabled ? 1.0 : 0.0, w.t0_c, w.sigma_t_c};
  std::lock_guard<std::mutex> lock(drive_->raw_cache_lock);
  auto it = drive_->factors.find(key);
  if (it == drive_->factors.end()) {
    DriveCellFactors factors;
    for (const DiagnosisRun& c : cells) {
      factors.area_per_speed_m_s.push_back(contactAreaPerSpeed(f, c.op));
      factors.file_thermal.push_back(w.temperature_enabled ? w.temperatureFactor(c.tread_temperature_c) : 1.0);
    }
    it = drive_->factors.emplace(key, std::move(factors)).first;
  }
  return it->second;
}

bool ExtendedModel::driveCellView(const std::vector<double>& values, const std::vector<RawResult>& raw,
                                  DriveCellView* view) const {
  const std::size_t n = data_.runs.size();
  const bool fine = !options_.coarse_cells_only;
  view->cells = fine ? &drive_->fine : &drive_->coarse;
  view->shares = fine ? &drive_->fine_shares : &drive_->coarse_shares;
  view->coarse = raw.data() + n;
  view->coarse_of_fine = &drive_->coarse_of_fine;
  view->factors = &cellFactors(fine);
  if (has(Term::kThermalWear))
    for (const DiagnosisRun& c : *view->cells) view->thermal.push_back(thermalW3(values, c.tread_temperature_c));
  if (has(Term::kAdhesionWear)) {
    // Models of one data set may predict on several threads (--jobs); std::map keeps the reference valid.
    const std::lock_guard<std::mutex> lock(drive_->raw_cache_lock);
    view->work = &cellAdhesionWork(base_, brush_options_.orientation, *view->cells,
                                   fine ? &drive_->fine_adhesion : &drive_->coarse_adhesion);
  }
  if (!fine) return true;
  try {
    view->fine_base = &baseCellResults(true);
    const BrushSetting s = brushSetting(values);
    const bool at_base = s.mu_scale == 1.0 && s.k_t == 0.0 && s.compliance == 0.0 && s.q == base_.friction.q;
    if (at_base) return true;
    const std::vector<RawResult>& coarse_base = baseCellResults(false);
    view->change.resize(coarse_base.size());
    for (std::size_t m = 0; m < coarse_base.size(); ++m)
      view->change[m] = {raw[n + m].fy_n - coarse_base[m].fy_n, raw[n + m].wear_w3_kg_per_m,
                         coarse_base[m].wear_w3_kg_per_m};
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

void ExtendedModel::predictSegment(const std::vector<double>& values, const DriveCellView& view, int run, double* fy_n,
                                   double* wear_kg_per_m) const {
  const DiagnosisRun& r = data_.runs[static_cast<std::size_t>(run)];
  const double w3_factor = w3Factor(values, r);
  const double w4_extra = has(Term::kContactTimeWear) ? values[parameterOffset(Term::kContactTimeWear)] : 0.0;
  const double k_a = has(Term::kAdhesionWear) ? values[parameterOffset(Term::kAdhesionWear)] : 0.0;
  double fy_sum = 0.0, wear_sum = 0.0;
  for (const DriveCells::Share& s : (*view.shares)[static_cast<std::size_t>(run)]) {
    const RawResult c = view.at(s.cell);
    const std::size_t k = static_cast<std::size_t>(s.cell);
    // The road wear terms (contact_time_wear, adhesion_wear): additive per distance, no brush re-evaluation.
    const double road = w4_extra * view.factors->area_per_speed_m_s[k] + k_a * (view.work ? (*view.work)[k] : 0.0);
    fy_sum += c.fy_n * s.time_s;
    wear_sum += (w3_factor * view.thermalFactor(s.cell) * c.wear_w3_kg_per_m + c.wear_w4_kg_per_m + road) * s.distance_m;
  }
  *fy_n = fy_sum / r.drive_time_s;
  *wear_kg_per_m = wear_sum / r.drive_distance_m;
}

bool ExtendedModel::predict(const std::vector<double>& values, Prediction* out) const {
  if (static_cast<int>(values.size()) != num_parameters_) return false;
  for (double v : values)
    if (!std::isfinite(v)) return false;
  const std::vector<RawResult>* found = rawResults(values);
  if (found == nullptr) return false;
  const std::vector<RawResult>& raw = *found;
  const int n = static_cast<int>(data_.runs.size());
  DriveCellView view;
  if (drive_ && !driveCellView(values, raw, &view)) return false;
  const double w4_extra = has(Term::kContactTimeWear) ? values[parameterOffset(Term::kContactTimeWear)] : 0.0;
  const double k_a = has(Term::kAdhesionWear) ? values[parameterOffset(Term::kAdhesionWear)] : 0.0;
  out->side_force_n.resize(n);
  out->wear_kg_per_m.resize(n);
  for (int i = 0; i < n; ++i) {
    const DiagnosisRun& r = data_.runs[i];
    double fy = raw[i].fy_n, wear = 0.0;
    if (r.isDrive()) {
      predictSegment(values, view, i, &fy, &wear);
    } else {
      wear = w3Factor(values, r) * thermalW3(values, r.tread_temperature_c) * raw[i].wear_w3_kg_per_m +
             raw[i].wear_w4_kg_per_m;
      if (w4_extra != 0.0 || k_a != 0.0)
        wear += w4_extra * contactAreaPerSpeed(base_.footprint, r.op) +
                k_a * (k_a != 0.0 ? adhesionWork(base_, brush_options_.orientation, {&r}).front() : 0.0);
    }
    if (has(Term::kSensorGain)) fy *= values[parameterOffset(Term::kSensorGain)];
    if (has(Term::kSensorOffset)) fy += values[parameterOffset(Term::kSensorOffset)];
    for (const auto& [offset, evaluator] : user_terms_) evaluator->apply(i, &values[offset], &fy, &wear);
    out->side_force_n[i] = fy;
    out->wear_kg_per_m[i] = wear;
    if (!std::isfinite(out->side_force_n[i]) || !std::isfinite(out->wear_kg_per_m[i])) return false;
  }
  return true;
}

std::atomic<long>& cellsEvaluated() {
  static std::atomic<long> count{0};
  return count;
}

}  // namespace diagnosis
}  // namespace tread_wear
