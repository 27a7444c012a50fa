#pragma once
/// @file conceal.h
/// Concealed-effect generator: recordings from the model plus one hidden library term (extensions.h: built-in or
/// user-defined, user_mechanisms.h) and rig-like noise, with the answer kept apart, so that the diagnosis can be
/// scored on cases with a known truth.
///
/// Designs (the paper's Table 2 program on the Grip and Abrasion Test Stand, rig as turn slip, R_t = 60 mm):
///   table2  three groups (velocity 1/2/3 m/s; slip angle 5/10/15 deg; load 50/75/100 N; otherwise 2 m/s,
///           10 deg, 75 N), two cycles per group, each cycle the three conditions twice (I II III I II III, the
///           second cycle reversed), durations of Table 2 (equal lateral sliding distance, Eq 1): 36 runs,
///           6 surface cycles.
///   small   one cycle per group: 18 runs (fast tests).
///   low_slip  table2 around 3 deg instead of 10 deg (sideslip group 1.5/3/6 deg; durations for the same lateral
///           sliding distance): small side forces, where an additive transducer noise is a large error ratio
///           (issue 26).
///   drives  road drives of a fleet (ConcealSpec::fleet) measured at checkpoints on every wheel, each run a drive
///           segment: drive_fleet.h. Hidden effects: a library term, or `rough_road` (kRoughRoadEffect), a
///           road-surface dependence that no library term has; wear only (no side force on drives).
/// Truth per case: w3_scale ~ exp(N(0, 0.15^2)) and mu_scale ~ exp(N(0, 0.04^2)) (the file's level is never
/// exact), plus the hidden term at the requested magnitude. Covariates a rig records: tread temperature
/// T = T_ambient(cycle) + 1.4 degC/W * Fy v sin(alpha) + N(0, 2^2) degC with T_ambient ~ 23 + N(0, 3^2) degC per
/// cycle; load std 4% of the load (times U(0.5, 1.5)) per run, or `magnitude` x load for load_fluctuation; an
/// unrelated humidity reading; the group label. Noise: side force + N(0, side_force_noise_n^2) [N], wear
/// x (1 + N(0, wear_noise_rsd^2)).
/// The hidden term's primary parameter is the magnitude (thermal_wear: sigma_T with T0 = 35 degC;
/// load_fluctuation: the relative load std, with the truth load_std_scale = 1; turn_slip_orientation: none;
/// rough_road: beta, neutral 0).

#include <cstdint>
#include <map>
#include <string>

#include "tread_wear/diagnosis/extensions.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/proving/drive_fleet.h"

namespace tread_wear {
namespace diagnosis {

struct ConcealSpec {
  std::string effect = "none";  ///< library name, "none", or (design drives) kRoughRoadEffect
  double magnitude = std::numeric_limits<double>::quiet_NaN();  ///< primary parameter; NaN = the default
  std::string design = "table2";                                ///< "table2", "small", "low_slip" or "drives"
  double wear_noise_rsd = 0.05;                                 ///< relative wear noise [-], >= 0
  double side_force_noise_n = 1.0;                              ///< side-force noise [N], >= 0
  std::uint64_t seed = 1;
  ExtendedModelOptions model;  ///< preset and orientation of the generating model (the tools: `reference`)
  DriveFleet fleet;            ///< the drive design's fleet and measurement plan (design drives only)

  bool validate(std::string* error) const;
};

/// The truth of one case.
struct ConcealAnswer {
  std::string effect;                        ///< library name or "none"
  std::map<std::string, double> parameters;  ///< every true parameter value (w3_scale, mu_scale, the term's)
  std::string primary;                       ///< name of the primary parameter ("" for none / orientation)
  double primary_value = std::numeric_limits<double>::quiet_NaN();
  double primary_neutral = std::numeric_limits<double>::quiet_NaN();  ///< NaN: compare relative to the value
  ConcealSpec spec;
};

struct ConcealCase {
  RunTable table;       ///< the recordings: truth plus noise
  RunTable noise_free;  ///< the same runs with the truth itself as measurements (detectability.h)
  ConcealAnswer answer;
};

/// Default magnitude of the drive design's rough_road effect: beta [-] (wear +-21% over the design's shares).
constexpr double kRoughRoadDefaultBeta = 0.7;
/// Name of rough_road's parameter beta in ConcealAnswer [-].
constexpr const char* kRoughRoadBetaName = "rough_road_beta";

/// Default magnitude of a term's primary parameter in generated cases; for a user-defined term (user_mechanisms.h)
/// the last of its test magnitudes, NaN without them (ConcealSpec::magnitude is then needed).
double defaultMagnitude(Term term);
/// A small and a large magnitude of a term's primary parameter for the harness's two-magnitude runs; for a
/// user-defined term its two test magnitudes. false for a term without two (the harness then uses the default).
bool smallAndLargeMagnitudes(Term term, double* small, double* large);
/// Generates one case. @throw std::invalid_argument for an invalid spec, an unknown effect or a user-defined one
/// without a magnitude or that the design cannot show; DiagnosisError for a user-defined one that does not reduce
/// to the model at its no-effect values.
ConcealCase concealEffect(const TireParams& base, const ConcealSpec& spec);
/// The truth of given recordings instead of a design's (e.g. a fleet's drive segments read from its bags,
/// ros/bag/diagnosis_bag.h): every run's wear rate under the base model at the file's levels (w3_scale = mu_scale =
/// 1) plus the hidden library term `effect` ("none": the base model) at `magnitude` (NaN: its default), evaluated by
/// ExtendedModel on the runs' cells at model.preset, as concealEffect's truth. No noise and no side force: the caller
/// measures (table and noise_free are the same). @throw std::invalid_argument for an unknown effect or one these
/// recordings cannot show (termApplicable), naming it.
ConcealCase concealInRecordings(const TireParams& base, const RunTable& recordings, const std::string& effect,
                                double magnitude, const ExtendedModelOptions& model);
}  // namespace diagnosis
}  // namespace tread_wear
