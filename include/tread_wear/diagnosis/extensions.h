#pragma once
/// @file extensions.h
/// The library of candidate extensions of the base model (paper Sections 2-4), each a named mechanism with
/// parameters, a one-line physical statement and the outputs it affects, and the extended model that
/// evaluates the base brush model (brush_wear_model.h) with any set of them switched on.
///
/// Base model: the parameter file's TireParams, evaluated at a preset, with two level parameters always free in
/// a calibration: w3_scale (multiplies the abrasion coefficient w3 of Eq 19) and mu_scale (multiplies mu_0 and
/// mu_m of Eq 10). Everything else comes from the file. Terms (ISO axes, SI; T tread temperature):
///   thermal_wear         w3 -> w3 exp((T - T0)^2 / (2 sigma_T^2))          Eq 25        wear
///   thermal_friction     mu_0, mu_m -> (1 - k_T (T - 23 degC)) mu_0, mu_m                side force, wear
///   surface_polishing    w3 -> w3 exp(-r_p L_cum)  (L_cum: cumulative sliding, reset per cycle)  wear
///   lateral_compliance   alpha_eff = alpha + c_lat Fy(alpha_eff)  (|alpha_eff| < |alpha|)  side force, wear
///   pressure_friction    sat(p) = (p / p_ref)^-q with q free (Eq 11)                       side force, wear
///   load_fluctuation     Eq 23 over N(Fz, (s_load std)^2), 3-point Gauss-Hermite           side force, wear
///   turn_slip_orientation  the other orientation of alpha against the track curve          side force, wear
///   sensor_gain          measured Fy = g Fy (force transducer gain; not physics)           side force
///   sensor_offset        measured Fy = Fy + o (force transducer zero offset; not physics)  side force
///   contact_time_wear    W_r += w4 4ab / V: the paper's non-sliding wear (Eq 19's per-time term) on top of the
///                        file's w4, a, b the footprint's at the load (no brush evaluation)            wear
///   adhesion_wear        W_r += K_a E_a: adhesion-zone micro-slip (model/adhesion_wear.h) on top of the file's,
///                        E_a at the base brush parameters (it does not follow mu_scale or the friction terms)  wear
/// The two wear terms of the road (contact_time_wear, adhesion_wear) apply to drive segments only: on the rig's
/// steady programmes they would compete with the rig's own terms, whose proofs were made without them.
/// User-defined mechanisms (user_mechanisms.h) follow the built-in terms in the library (Term::kFirstUser on) and
/// are applied after them, in the order of the model's terms.
/// W_r splits exactly into the w3 part and the w4 part w4 4ab/V (Eq 19-20: w4 acts on the whole patch), so the
/// terms that scale w3 (w3_scale, thermal_wear, surface_polishing) are applied after the brush evaluation.
/// Eq 23 for a normal load distribution is the integral of W_r(Fz) over N(mean, std^2); the paper's 10 N bins are
/// one quadrature of it. The 3-point Gauss-Hermite rule (nodes mean, mean +- sqrt(3) std; weights 2/3, 1/6, 1/6)
/// is exact for polynomials up to degree 5 and smooth in s_load, which a least-squares Jacobian needs.
/// Lateral compliance solves alpha_eff = alpha + c_lat Fy(alpha_eff) by secant iteration, the first step exact for a
/// linear tire (the root is unique where Fy falls with the slip angle).
/// Drive segments (DiagnosisRun::isDrive) are predicted from their integrated operating points, binned into cells
/// (point_cells.h) at two resolutions that all segments share: fine cells (the default PointCellParams, within
/// 0.25% of the replay's wear per segment, docs/diagnosis.md) and coarse ones (4 times the load width, 5 times the
/// slip widths, 15 times the speed width, 6 times the curvature width, 3 degC; about 8 times fewer cells). The fine
/// cells are evaluated once per preset at the base brush parameters (mu_scale 1, no friction, compliance or spread
/// term; cached with the data: DiagnosisData::drive_cells); a fit re-simulates only the coarse cells and carries the
/// change to the fine cells it contains:
///   Fy = Fy_fine,base + (Fy_coarse - Fy_coarse,base),  W_r,w3 = W_r,w3,fine,base x W_r,w3,coarse / W_r,w3,coarse,base,
/// W_r,w4 (load and speed only) from the fine cell. A change of the parameters moves W_r smoothly across a coarse
/// cell, so the ratio carries it to second order where W_r itself (steep in slip) would not. A segment's W_r is
/// the distance-weighted sum over its fine cells (Fy the time-weighted one). Terms act per cell where they
/// depend on the point (the thermal terms on the cell's temperature, the friction and compliance terms through the
/// brush evaluation) and per segment otherwise (surface_polishing, the sensor terms, user terms on the segment's
/// means and covariates).
/// Limits: steady state per run or per drive point; a steady run's temperature is its recorded mean tread
/// temperature.

#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "tread_wear/diagnosis/data.h"
#include "tread_wear/fitting/least_squares.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/model/wear_model.h"

namespace tread_wear {
namespace diagnosis {

/// A term of the library: the built-in terms, then the user-defined ones (kFirstUser + i).
enum class Term {
  kNone = -1,  ///< no term (e.g. a control without a hidden effect)
  kThermalWear = 0,
  kThermalFriction,
  kSurfacePolishing,
  kLateralCompliance,
  kPressureFriction,
  kLoadFluctuation,
  kTurnSlipOrientation,
  kSensorGain,
  kSensorOffset,
  kContactTimeWear,
  kAdhesionWear,
  kFirstUser  ///< the first user-defined term, if any
};

struct UserMechanism;
class MechanismEvaluator;
struct DriveCells;
struct DriveNodeColumn;
struct DriveCellFactors;
struct DriveCellView;

struct TermParameterSpec {
  std::string name;     ///< e.g. "compliance_rad_per_n"
  double initial;       ///< start of a fit [unit]
  double lower, upper;  ///< bounds [unit]
  bool log_scale;       ///< fit ln(value)
  double neutral;       ///< value at which the term has no effect [unit]; NaN when there is none (sigma_T -> inf)
  std::string unit;     ///< e.g. "rad/N", "-" for a dimensionless one
};

struct TermInfo {
  Term term;
  std::string name;                           ///< library name, e.g. "surface_polishing"
  std::string statement;                      ///< one-line physical statement
  bool physical;                              ///< false for the sensor terms
  bool affects[kNumOutputs];                  ///< side force, wear
  std::vector<TermParameterSpec> parameters;  ///< empty for turn_slip_orientation (a discrete switch)
  int primary;                                ///< index of the parameter that measures the effect's size; -1 for none
  double temperature_ref_c = 23.0;            ///< thermal_friction reference temperature [degC] (the rig's ambient)
  std::shared_ptr<const UserMechanism> user = nullptr;  ///< a user-defined mechanism's expression; null if built in
};

/// All terms, in enum order: the built-in ones, then the user-defined ones.
const std::vector<TermInfo>& termLibrary();
/// Replaces the user-defined terms of the library by `user` (numbered from Term::kFirstUser on) and returns the
/// previous ones. Not thread-safe, and it invalidates references into the library: call it before any diagnosis
/// runs (user_mechanisms.h, MechanismsInUse).
std::vector<TermInfo> setUserTerms(std::vector<TermInfo> user);
/// Makes `lib` the library of the calling thread only (the shared one plus terms of its own, numbered on from its
/// last: the empirical terms, empirical.h), until it is set back; null = the shared library. `lib` must outlive
/// its use. Returns the previous setting. Other threads keep the shared library, so a harness's workers can each
/// fit their own empirical terms.
const std::vector<TermInfo>* setThreadLibrary(const std::vector<TermInfo>* lib);
const TermInfo& termInfo(Term term);
/// Whether the term has a single parameter whose no-effect value is one of its bounds (the effect can only go
/// one way: surface_polishing, lateral_compliance, load_fluctuation).
bool neutralOnBound(const TermInfo& info);
/// The value of the term's primary parameter at which it has no effect: its `neutral`, except pressure_friction's
/// q, which is the parameter file's. NaN without one (sigma_T -> infinity, the orientation switch).
double primaryNeutral(Term term, const TireParams& base);
/// Library name to term; false for an unknown name.
bool parseTerm(const std::string& name, Term* term);
/// Whether the data can show the term (temperatures recorded, sequence known, load std recorded, turn slip
/// present, side force measured; a user term's variables known on every run); otherwise *why_not says what is
/// missing.
bool termApplicable(Term term, const DiagnosisData& data, std::string* why_not);
/// Unit of a model parameter by name (the base levels and every library term's), "" for an unknown name.
std::string parameterUnit(const std::string& name);
/// "a+b" for a combination, "none" for no term.
std::string termsLabel(const std::vector<Term>& terms);

/// Predictions for every run of the data.
struct Prediction {
  std::vector<double> side_force_n;
  std::vector<double> wear_kg_per_m;
  double value(Output o, int run) const { return o == Output::kSideForce ? side_force_n[run] : wear_kg_per_m[run]; }
};

struct ExtendedModelOptions {
  Preset preset = Preset::kFast;                                    ///< resolution of the brush model
  TurnSlipOrientation orientation = TurnSlipOrientation::kLiteral;  ///< base orientation
  /// Drive segments on the coarse cells only (the solver-error check: the difference of two presets varies
  /// little across a coarse cell); otherwise fine cells with the coarse correction (see the file comment).
  bool coarse_cells_only = false;
  /// Drive segments: with no pressure, compliance or spread term away from its no-effect value, a coarse cell's
  /// results are interpolated (Catmull-Rom, in the ln of its friction factor: mu_scale times thermal_friction's
  /// factor at the cell's temperature) between results at nodes kMuScaleNodeSpacing apart, each evaluated once
  /// per cell and shared by every fit of the diagnosis (a fit of mu_scale or k_T then re-simulates a few nodes
  /// instead of every cell at every trial value). Off: each friction factor is evaluated as it is (the
  /// solver-error check, which compares presets cell by cell).
  bool interpolate_mu_scale = true;
  /// Threads evaluating the brush model's cells and runs (parallel_for.h); the results do not depend on it, >= 1
  int jobs = 1;
};

/// Spacing of the mu_scale nodes of ExtendedModelOptions::interpolate_mu_scale, in ln mu_scale [-]: 1% of friction.
/// A segment's interpolated W_r is within 6e-5 of the direct evaluation at mu_scale 0.937 (test
/// InterpolatedFrictionMatchesTheDirectEvaluation), against the coarse cells' own 0.5%.
constexpr double kMuScaleNodeSpacing = 0.01;

/// A coarse drive cell's part of one drive segment's predictions (ExtendedModel::coarseCellContributions).
struct CellContribution {
  int run;               ///< index of the segment in the data
  double side_force_n;   ///< its share of the segment's time-weighted Fy (times a sensor gain) [N]
  double wear_kg_per_m;  ///< its share of the segment's distance-weighted W_r [kg/m]
};

/// The base model plus a set of terms, with parameters laid out as [w3_scale, mu_scale, term parameters...].
/// Not thread-safe (it caches brush evaluations); use one per thread.
class ExtendedModel {
 public:
  /// @throw std::invalid_argument for invalid parameters or a term listed twice.
  ExtendedModel(const TireParams& base, const ExtendedModelOptions& options, std::vector<Term> terms,
                const DiagnosisData& data);

  /// Free parameters with start values and bounds (term starts adapted to the data, e.g. T0).
  std::vector<FitParameter> parameters() const;
  /// The start points of a fit from `params`: `params` itself, or, with thermal_wear on and T0 not given by the
  /// caller, three starts with T0 below, inside and above the observed tread temperatures (Eq 25 is a bowl in T).
  std::vector<std::vector<FitParameter>> fitStarts(const std::vector<FitParameter>& params, bool t0_given) const;
  const std::vector<Term>& terms() const { return terms_; }
  /// Index of the first parameter of a term in the layout, -1 if the term is not active.
  int parameterOffset(Term term) const;
  /// Predicts all runs. Returns false when the brush model cannot be evaluated at these values.
  bool predict(const std::vector<double>& values, Prediction* out) const;
  /// With coarse_cells_only: evaluates the brush model at `values` at the listed coarse cells only (uncached; the
  /// solver-error check's sample, numerics_check.h) and gives each cell's contributions to the segments that
  /// share it. A drive segment's coarse prediction (predict) is the sum of its cells' contributions, plus a sensor
  /// offset and user terms, which act per segment; the difference of two presets' contributions is therefore the
  /// cell's part of the segments' solver error. Returns false when the model cannot be evaluated there.
  /// @throw std::logic_error without coarse_cells_only.
  bool coarseCellContributions(const std::vector<double>& values, const std::vector<int>& cells,
                               std::vector<std::vector<CellContribution>>* out) const;
  /// The coarse drive cells shared by all segments (0 without drive segments).
  std::size_t coarseCellCount() const;
  /// Operating points the brush model is evaluated at per new set of brush-relevant parameter values: the distinct
  /// steady conditions plus the coarse cells of all drive segments together (drive cells, below).
  std::size_t evaluationPoints() const;
  /// The fine drive cells, evaluated once per preset at the base brush parameters (0 without drive segments).
  std::size_t fineDriveCells() const;
  /// Brush evaluations so far: only a change of a brush-relevant parameter (mu_scale, a friction, compliance or
  /// load-spread term) re-simulates; w3_scale, thermal_wear, surface_polishing, the sensor terms and user terms
  /// act on cached results. The drive cells' one evaluation at the base parameters is not counted here.
  long brushEvaluations() const { return brush_evaluations_; }

  /// Brush model results at one point: Fy and W_r split into its w3 and w4 parts (Eqs 19-20).
  struct RawResult {
    double fy_n;
    double wear_w3_kg_per_m;  ///< w3 part of W_r (at the file's w3)
    double wear_w4_kg_per_m;  ///< w4 part of W_r
  };

 private:
  /// The brush-relevant parameters of a parameter vector: they decide whether a prediction re-simulates.
  struct BrushSetting {
    double mu_scale, k_t, compliance, q, load_std_scale;
  };
  BrushSetting brushSetting(const std::vector<double>& values) const;
  /// Brush results at `setting` for each non-null point, on options_.jobs threads; false outside the terms'
  /// validity. @throw what the brush model throws.
  bool evaluatePoints(const BrushSetting& setting, const std::vector<const DiagnosisRun*>& points,
                      std::vector<RawResult>* raw) const;
  /// The w3 factor of a segment or run (w3_scale, surface_polishing) and the thermal factor at a temperature.
  double w3Factor(const std::vector<double>& values, const DiagnosisRun& run) const;
  double thermalW3(const std::vector<double>& values, double temperature_c) const;
  /// The brush results of the steady runs (0..n-1) and the coarse drive cells (n..) at `values`, from the cache
  /// or evaluated; null when the model cannot be evaluated there.
  const std::vector<RawResult>* rawResults(const std::vector<double>& values) const;
  /// The steady runs evaluated as they are and the coarse cells interpolated in mu_scale between nodes
  /// (interpolate_mu_scale); null when a node cannot be evaluated.
  std::vector<RawResult> interpolatedResults(const BrushSetting& setting, bool* ok) const;
  /// Whether the coarse cells at `setting` are interpolated (interpolate_mu_scale, the other brush parameters at
  /// their no-effect values).
  bool interpolates(const BrushSetting& setting) const;
  /// The coarse cells at a node of the friction factor, with at least `cells` evaluated (from the data's node
  /// cache, the missing ones evaluated into it); null when they cannot be evaluated.
  const DriveNodeColumn* nodeColumn(long node, const std::vector<int>& cells) const;
  /// The brush results of the steady runs and coarse cells at `setting` (points with a null entry are skipped).
  std::vector<const DiagnosisRun*> brushPoints(bool steady, bool coarse) const;
  /// The fine (or coarse) drive cells evaluated at the base brush parameters, once per preset key (cached with the
  /// data). @throw what the brush model throws.
  const std::vector<RawResult>& baseCellResults(bool fine) const;
  /// The fine (or coarse) drive cells' wear factors that do not depend on the parameters (cached with the data).
  const DriveCellFactors& cellFactors(bool fine) const;
  /// The drive cells' results at `values` (`raw`: rawResults); false when they cannot be evaluated.
  bool driveCellView(const std::vector<double>& values, const std::vector<RawResult>& raw, DriveCellView* view) const;
  /// A drive segment's Fy (time-weighted) and W_r (distance-weighted) over its cells, before the sensor and user
  /// terms.
  void predictSegment(const std::vector<double>& values, const DriveCellView& view, int run, double* fy_n,
                      double* wear_kg_per_m) const;
  /// What the cached results of the drive cells depend on besides the brush parameters: the preset, the
  /// orientation and the tire file's friction and wear levels.
  std::vector<double> presetKey() const;
  bool has(Term t) const { return parameterOffset(t) >= 0; }
  RawResult evaluateRun(const BrushWearModel& model, const DiagnosisRun& run, double compliance,
                        double load_std_scale) const;

  TireParams base_;
  ExtendedModelOptions options_;
  std::vector<Term> terms_;
  std::vector<int> offsets_;
  int num_parameters_ = 0;
  /// The active user terms' expressions with the offsets of their parameters, in the order of terms_.
  std::vector<std::pair<int, std::shared_ptr<MechanismEvaluator>>> user_terms_;
  const DiagnosisData& data_;
  BrushOptions brush_options_;
  std::size_t distinct_steady_ = 0;    ///< distinct conditions of the steady runs
  std::shared_ptr<DriveCells> drive_;  ///< the data's drive cells (null without drive segments)
  mutable long brush_evaluations_ = 0;
  /// Brush results for the last few values of the brush-relevant parameters: the steady runs, then the coarse
  /// drive cells (the post-processing terms, e.g. thermal_wear or the sensor terms, reuse them: their Jacobian
  /// columns cost no brush solve).
  mutable std::map<std::vector<double>, std::vector<RawResult>> cache_;
};

/// Brush evaluations of runs and cells by every ExtendedModel of the process so far (progress reports).
std::atomic<long>& cellsEvaluated();

}  // namespace diagnosis
}  // namespace tread_wear
