#pragma once
/// @file reference_models.h
/// The paper's conventional reference wear models (Section 4.2, Eq 26, Table 5): a GLOBAL friction-power law
/// driven by the measured side force and the lateral slip speed,
///     W_r = (w4 + w3 (Fy / 1 N)^w1 (v0 sin(alpha) / 1 m/s)^w2) / v0          (Eq 26)
/// with w3, w4 in mg/s (global, not per contact area; SI here: kg/s) and W_r in kg/m.
///   M_P:   w1 = w2 (friction power),             no temperature
///   M_EP:  w1, w2 free (generalised power),      no temperature
///   M_PT, M_EPT: the same with the Eq 25 factor exp((T - T0)^2 / (2 sigma_T^2)) on w3 (needs tread temperatures).
/// Inputs: the paper bins the recorded side force of each run (10 N bins, Eq 23); a run table of means gives
/// one value per run, so the measured mean side force is used (one bin). Fy and alpha enter by magnitude.
/// Fits use the least-squares engine on error ratios (Eq 24) with leave-one-condition-out cross-validation.

#include <limits>
#include <string>
#include <vector>

#include "tread_wear/fitting/least_squares.h"
#include "tread_wear/io/run_table.h"

namespace tread_wear {

enum class ReferenceModelKind { kP, kPT, kEP, kEPT };
/// "M_P", "M_PT", "M_EP", "M_EPT".
const char* referenceModelName(ReferenceModelKind kind);
bool referenceModelUsesTemperature(ReferenceModelKind kind);

/// Eq 26 (and Eq 25 for the temperature variants). Defaults: Table 5, M_EP.
struct ReferenceWearLaw {
  double w1 = 1.11;                 ///< side-force exponent [-]
  double w2 = 1.48;                 ///< slip-speed exponent [-]
  double w3_kg_per_s = 7.22e-8;     ///< abrasion coefficient [kg/s] (Table 5: 7.22e-2 mg/s)
  double w4_kg_per_s = 0.11e-8;     ///< offset wear [kg/s] (Table 5: 0.11e-2 mg/s)
  bool temperature_enabled = false; ///< apply Eq 25
  double t0_c = 0.0;                ///< Eq 25 reference temperature [degC]
  double sigma_t_c = 1.0;           ///< Eq 25 width [degC], != 0

  bool validate(std::string* error) const;
  /// Eq 26 [kg/m]. speed_mps > 0; temperature NaN = unknown (no Eq 25 factor).
  double wearRate_kg_per_m(double side_force_n, double speed_mps, double slip_angle_rad,
                           double tread_temperature_c = std::numeric_limits<double>::quiet_NaN()) const;
};

/// Table 5 parameters of the paper for a model kind.
ReferenceWearLaw paperReferenceLaw(ReferenceModelKind kind);

struct ReferenceFit {
  ReferenceModelKind kind = ReferenceModelKind::kP;
  ReferenceWearLaw law;               ///< fitted
  LeastSquaresSummary summary;        ///< parameters named w1 (= w2 for M_P), w2, w3, w4[, T0, sigma_T]
  std::vector<double> predicted_kg_per_m;     ///< per run, in sample
  std::vector<double> cv_predicted_kg_per_m;  ///< per run, fitted without the run's condition_id
  double rmse_kg_per_m = 0.0, rmser = 0.0;        ///< Eqs 21, 24 in sample
  double cv_rmse_kg_per_m = 0.0, cv_rmser = 0.0;  ///< leave-one-condition-out
};

/// Fits a reference model to the runs with measured side force and wear rate, starting from `start`.
/// @throw std::invalid_argument when no run has both measurements, or a temperature variant is asked for and
/// a run has no tread temperature (nothing is invented).
ReferenceFit fitReferenceModel(ReferenceModelKind kind, const RunTable& runs, const ReferenceWearLaw& start,
                               const LeastSquaresOptions& options = {});

}  // namespace tread_wear
