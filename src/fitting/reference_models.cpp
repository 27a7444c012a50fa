#include "tread_wear/fitting/reference_models.h"

#include <cmath>
#include <stdexcept>

#include "tread_wear/fitting/metrics.h"
#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMgPerSToKgPerS = 1e-6;

bool tiedExponents(ReferenceModelKind k) { return k == ReferenceModelKind::kP || k == ReferenceModelKind::kPT; }

/// Law from a fitted parameter vector laid out as {w1[, w2], w3, w4[, T0, sigma_T]}.
ReferenceWearLaw lawFrom(ReferenceModelKind kind, const std::vector<double>& v) {
  ReferenceWearLaw law;
  size_t i = 0;
  law.w1 = v[i++];
  law.w2 = tiedExponents(kind) ? law.w1 : v[i++];
  law.w3_kg_per_s = v[i++];
  law.w4_kg_per_s = v[i++];
  law.temperature_enabled = referenceModelUsesTemperature(kind);
  if (law.temperature_enabled) {
    law.t0_c = v[i++];
    law.sigma_t_c = v[i++];
  }
  return law;
}

}  // namespace

const char* referenceModelName(ReferenceModelKind kind) {
  switch (kind) {
    case ReferenceModelKind::kP: return "M_P";
    case ReferenceModelKind::kPT: return "M_PT";
    case ReferenceModelKind::kEP: return "M_EP";
    case ReferenceModelKind::kEPT: return "M_EPT";
  }
  return "unknown";
}

bool referenceModelUsesTemperature(ReferenceModelKind kind) {
  return kind == ReferenceModelKind::kPT || kind == ReferenceModelKind::kEPT;
}

bool ReferenceWearLaw::validate(std::string* error) const {
  auto fail = [&](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (!std::isfinite(w1) || !std::isfinite(w2)) return fail("w1, w2 must be finite");
  if (!(w3_kg_per_s >= 0.0)) return failValidation(error, "w3_kg_per_s", w3_kg_per_s, ">= 0");
  if (!(w4_kg_per_s >= 0.0)) return failValidation(error, "w4_kg_per_s", w4_kg_per_s, ">= 0");
  if (temperature_enabled && !(std::isfinite(t0_c) && std::isfinite(sigma_t_c) && sigma_t_c != 0.0))
    return failValidation(error, "sigma_t_c", sigma_t_c, "finite and != 0 (T0 finite)");
  return true;
}

double ReferenceWearLaw::wearRate_kg_per_m(double side_force_n, double speed_mps, double slip_angle_rad,
                                           double tread_temperature_c) const {
  const double slip_speed_mps = speed_mps * std::abs(std::sin(slip_angle_rad));
  double w3 = w3_kg_per_s;
  if (temperature_enabled && std::isfinite(tread_temperature_c)) {
    const double d = tread_temperature_c - t0_c;
    w3 *= std::exp(d * d / (2.0 * sigma_t_c * sigma_t_c));  // Eq 25 as printed (see tire_params.h)
  }
  return (w4_kg_per_s + w3 * std::pow(std::abs(side_force_n), w1) * std::pow(slip_speed_mps, w2)) / speed_mps;
}

ReferenceWearLaw paperReferenceLaw(ReferenceModelKind kind) {
  // Table 5: w3, w4 printed in 1e-2 mg/s.
  ReferenceWearLaw law;
  auto set = [&](double w1, double w2, double w3, double w4, double t0, double sigma) {
    law.w1 = w1;
    law.w2 = w2;
    law.w3_kg_per_s = w3 * 1e-2 * kMgPerSToKgPerS;
    law.w4_kg_per_s = w4 * 1e-2 * kMgPerSToKgPerS;
    law.temperature_enabled = std::isfinite(t0);
    law.t0_c = std::isfinite(t0) ? t0 : 0.0;
    law.sigma_t_c = std::isfinite(sigma) ? sigma : 1.0;
  };
  switch (kind) {
    case ReferenceModelKind::kP: set(1.36, 1.36, 2.32, 9.53, kNaN, kNaN); break;
    case ReferenceModelKind::kPT: set(1.14, 1.14, 3.73, 3.82, 80.19, 3.48); break;
    case ReferenceModelKind::kEP: set(1.11, 1.48, 7.22, 0.11, kNaN, kNaN); break;
    case ReferenceModelKind::kEPT: set(0.90, 1.27, 6.56, 5.71, 145.36, -115.58); break;
  }
  return law;
}

ReferenceFit fitReferenceModel(ReferenceModelKind kind, const RunTable& runs, const ReferenceWearLaw& start,
                               const LeastSquaresOptions& options) {
  const bool temperature = referenceModelUsesTemperature(kind);
  std::vector<int> used;
  for (size_t i = 0; i < runs.runs.size(); ++i) {
    const RunRecord& r = runs.runs[i];
    if (!(std::isfinite(r.measured_side_force_n) && std::isfinite(r.measured_wear_rate_kg_per_m) &&
          r.measured_wear_rate_kg_per_m > 0.0 && r.op.speed_mps > 0.0))
      continue;
    if (temperature && !std::isfinite(r.op.tread_temperature_c))
      throw std::invalid_argument(std::string(referenceModelName(kind)) + ": run " + std::to_string(i + 1) + " (" +
                                  r.condition_id + ") has no tread_temperature_c; temperature models need one per run");
    used.push_back(static_cast<int>(i));
  }
  if (used.empty()) throw std::invalid_argument("reference model: no run has measured side force and wear rate");

  LeastSquaresProblem problem;
  problem.num_records = static_cast<int>(used.size());
  for (int i : used) problem.groups.push_back(runs.runs[i].condition_id);
  problem.parameters.push_back({"w1", start.w1, 0.0, 5.0, false});
  if (!tiedExponents(kind)) problem.parameters.push_back({"w2", start.w2, 0.0, 5.0, false});
  problem.parameters.push_back({"w3", start.w3_kg_per_s, 1e-15, 1e-3, true});
  problem.parameters.push_back({"w4", start.w4_kg_per_s, 0.0, 1e-5, false});
  if (temperature) {
    problem.parameters.push_back({"T0", start.t0_c, -50.0, 250.0, false});
    problem.parameters.push_back({"sigma_T", std::abs(start.sigma_t_c), 0.5, 1000.0, true});
  }
  auto predict = [&](const ReferenceWearLaw& law, int run) {
    const RunRecord& r = runs.runs[run];
    return law.wearRate_kg_per_m(r.measured_side_force_n, r.op.speed_mps, r.op.slip_angle_rad,
                                 r.op.tread_temperature_c);
  };
  problem.residuals = [&](const std::vector<double>& v, const std::vector<int>& records, double* res) {
    const ReferenceWearLaw law = lawFrom(kind, v);
    for (size_t k = 0; k < records.size(); ++k) {
      const int run = used[records[k]];
      res[k] = predict(law, run) / runs.runs[run].measured_wear_rate_kg_per_m - 1.0;
    }
    return true;
  };

  ReferenceFit fit;
  fit.kind = kind;
  fit.summary = solveLeastSquares(problem, options);
  fit.law = lawFrom(kind, fit.summary.values());
  const CrossValidationResult cv = crossValidate(problem, options);
  std::vector<double> measured;
  for (size_t k = 0; k < used.size(); ++k) {
    measured.push_back(runs.runs[used[k]].measured_wear_rate_kg_per_m);
    fit.predicted_kg_per_m.push_back(predict(fit.law, used[k]));
    fit.cv_predicted_kg_per_m.push_back(measured.back() * (1.0 + cv.held_out_residuals[k]));
  }
  fit.rmse_kg_per_m = rmse(measured, fit.predicted_kg_per_m);
  fit.rmser = rmser(measured, fit.predicted_kg_per_m);
  bool cv_complete = true;
  for (double v : fit.cv_predicted_kg_per_m) cv_complete = cv_complete && std::isfinite(v);
  fit.cv_rmse_kg_per_m = cv_complete ? rmse(measured, fit.cv_predicted_kg_per_m) : kNaN;
  fit.cv_rmser = cv_complete ? rmser(measured, fit.cv_predicted_kg_per_m) : kNaN;
  return fit;
}

}  // namespace tread_wear
