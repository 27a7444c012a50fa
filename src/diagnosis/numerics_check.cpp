#include "tread_wear/diagnosis/numerics_check.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace tread_wear {
namespace diagnosis {
namespace {

/// Forward-difference step of the Jacobian, as a fraction of a parameter's scale (|value|, or its bound range when
/// the value is 0): large against the fixed grid's round-off, small against the model's curvature.
constexpr double kJacobianStep = 0.01;

}  // namespace

NumericsCheck checkNumerics(const TireParams& base, const DiagnosisData& data, const ExtendedModelOptions& options,
                            const std::vector<Term>& terms, const std::vector<double>& values,
                            const NoiseModel noise[kNumOutputs], double limit) {
  NumericsCheck c;
  c.at_model = termsLabel(terms);
  c.preset = options.preset;
  c.limit = limit;
  if (options.preset == Preset::kReference) return c;
  c.checked = true;
  ExtendedModelOptions preset_options = options;
  preset_options.coarse_drive_cells = true;  // drive segments: the presets' difference on the coarse cells
  const ExtendedModel coarse(base, preset_options, terms, data);
  ExtendedModelOptions finer_options = preset_options;
  finer_options.preset = c.finer;
  const ExtendedModel finer(base, finer_options, terms, data);
  Prediction at, ref;
  if (!coarse.predict(values, &at) || !finer.predict(values, &ref))
    throw std::invalid_argument("numerics check: the model '" + c.at_model + "' cannot be evaluated at its fit");

  // Rows: the measured values, weighted by 1/sigma.
  std::vector<std::pair<int, int>> rows;  // (run, output)
  for (std::size_t i = 0; i < data.runs.size(); ++i)
    for (int o = 0; o < kNumOutputs; ++o)
      if (std::isfinite(data.runs[i].measured[o])) rows.emplace_back(static_cast<int>(i), o);
  const int m = static_cast<int>(rows.size());
  Eigen::VectorXd wd(m);
  for (int r = 0; r < m; ++r) {
    const auto [i, o] = rows[r];
    const Output out = static_cast<Output>(o);
    const double sigma = noise[o].sigma(data.runs[i].measured[o]);
    const double d = ref.value(out, i) - at.value(out, i);
    wd(r) = d / sigma;
    NumericsOutput& s = c.outputs[o];
    ++s.values;
    s.noncentrality_raw += wd(r) * wd(r);
    const double rel = d / at.value(out, i);
    s.rms_relative += rel * rel;
    s.max_relative = std::max(s.max_relative, std::abs(rel));
  }
  for (NumericsOutput& s : c.outputs)
    if (s.values > 0) {
      s.rms_in_noise = std::sqrt(s.noncentrality_raw / s.values);
      s.rms_relative = std::sqrt(s.rms_relative / s.values);
    }

  // The weighted Jacobian of the coarse predictions in the fitted parameters.
  const std::vector<FitParameter> params = coarse.parameters();
  Eigen::MatrixXd wj(m, static_cast<int>(values.size()));
  for (std::size_t j = 0; j < values.size(); ++j) {
    const FitParameter& p = params[j];
    const double scale = values[j] != 0.0 ? std::abs(values[j]) : 0.5 * (p.upper - p.lower);
    double h = kJacobianStep * scale;
    if (values[j] + h > p.upper) h = -h;
    std::vector<double> moved = values;
    moved[j] += h;
    Prediction pm;
    if (!coarse.predict(moved, &pm)) {  // outside the term's validity that way: the other way
      h = -h;
      moved[j] = values[j] + h;
      if (!coarse.predict(moved, &pm))
        throw std::invalid_argument("numerics check: the model '" + c.at_model + "' cannot be evaluated near its fit");
    }
    for (int r = 0; r < m; ++r) {
      const auto [i, o] = rows[r];
      const Output out = static_cast<Output>(o);
      wj(r, static_cast<int>(j)) = (pm.value(out, i) - at.value(out, i)) / h / noise[o].sigma(data.runs[i].measured[o]);
    }
  }
  // Residual of W d after its least-squares projection onto the columns of W J (rank-revealing, so a parameter
  // without effect on these runs changes nothing).
  const Eigen::VectorXd coefficients = wj.colPivHouseholderQr().solve(wd);
  c.noncentrality = (wd - wj * coefficients).squaredNorm();
  c.passed = c.noncentrality <= limit;
  return c;
}

std::string numericsSummary(const NumericsCheck& c) {
  if (!c.checked) return std::string("not checked at ") + presetName(c.preset) + " (the finest grid of the model)";
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "solver error of %s against %s at '%s': lambda %.3g against the limit %.3g (side force %.3g sigma "
                "RMS, %.3g%% RMS; wear %.3g sigma RMS, %.3g%% RMS)",
                presetName(c.preset), presetName(c.finer), c.at_model.c_str(), c.noncentrality, c.limit,
                c.outputs[0].rms_in_noise, 100.0 * c.outputs[0].rms_relative, c.outputs[1].rms_in_noise,
                100.0 * c.outputs[1].rms_relative);
  return buf;
}

}  // namespace diagnosis
}  // namespace tread_wear
