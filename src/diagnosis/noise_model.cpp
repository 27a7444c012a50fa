#include "tread_wear/diagnosis/noise_model.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace tread_wear {
namespace diagnosis {
namespace {

constexpr int kShapeSteps = 200;  ///< grid of the combined model's shape t: 0, 1/200, ..., 1

/// -2 ln L of deviations e with variances c v_i at the ML size c; *c_out gets c.
double profileDeviance(const std::vector<double>& e, const std::vector<double>& v, double* c_out) {
  double c = 0.0, log_v = 0.0;
  const double n = static_cast<double>(e.size());
  for (std::size_t i = 0; i < e.size(); ++i) {
    c += e[i] * e[i] / v[i];
    log_v += std::log(v[i]);
  }
  c /= n;
  if (c_out) *c_out = c;
  if (!(c > 0.0)) return -std::numeric_limits<double>::infinity();  // exact fit: any model is perfect
  return n * std::log(2.0 * M_PI) + log_v + n * std::log(c) + n;
}

struct ShapeFit {
  double deviance = 0.0, c = 0.0, t = 0.0, m2 = 0.0;
};

ShapeFit fitShape(const std::vector<double>& e, const std::vector<double>& y, double t) {
  ShapeFit f;
  f.t = t;
  for (double v : y) f.m2 += v * v / static_cast<double>(y.size());
  std::vector<double> var(e.size());
  for (std::size_t i = 0; i < e.size(); ++i) var[i] = (1.0 - t) * f.m2 + t * y[i] * y[i];
  f.deviance = profileDeviance(e, var, &f.c);
  return f;
}

NoiseModel modelOf(NoiseKind kind, const ShapeFit& f) {
  NoiseModel m;
  m.kind = kind;
  m.additive = std::sqrt(f.c * (1.0 - f.t) * f.m2);
  m.relative = std::sqrt(f.c * f.t);
  return m;
}

}  // namespace

const char* noiseKindName(NoiseKind kind) {
  switch (kind) {
    case NoiseKind::kAdditive:
      return "additive";
    case NoiseKind::kRelative:
      return "relative";
    case NoiseKind::kCombined:
      return "combined";
  }
  return "?";
}

bool parseNoiseKind(const std::string& name, NoiseKind* kind) {
  for (NoiseKind k : {NoiseKind::kAdditive, NoiseKind::kRelative, NoiseKind::kCombined})
    if (name == noiseKindName(k)) {
      *kind = k;
      return true;
    }
  return false;
}

double NoiseModel::sigma(double y) const { return std::sqrt(additive * additive + relative * relative * y * y); }

NoiseModel NoiseModel::scaled(double factor) const {
  NoiseModel m = *this;
  m.additive *= factor;
  m.relative *= factor;
  return m;
}

bool NoiseModel::validate(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = "noise model: " + m;
    return false;
  };
  if (!(additive >= 0.0) || !std::isfinite(additive)) return fail("additive must be finite and >= 0");
  if (!(relative >= 0.0) || !std::isfinite(relative)) return fail("relative must be finite and >= 0");
  if (!(additive > 0.0 || relative > 0.0)) return fail("additive or relative must be > 0");
  return true;
}

NoiseSelection fitNoiseModel(NoiseKind kind, const std::vector<double>& e, const std::vector<double>& y) {
  if (e.size() != y.size()) throw std::invalid_argument("noise model: deviations and levels differ in size");
  if (e.size() < 3) throw std::invalid_argument("noise model: needs at least 3 deviations");
  const int n = static_cast<int>(e.size());
  NoiseSelection s;
  s.values = n;
  const ShapeFit additive = fitShape(e, y, 0.0), relative = fitShape(e, y, 1.0);
  ShapeFit combined = additive;
  for (int k = 0; k <= kShapeSteps; ++k) {
    const ShapeFit f = fitShape(e, y, static_cast<double>(k) / kShapeSteps);
    if (f.deviance < combined.deviance) combined = f;
  }
  // AICc of a Gaussian likelihood: -2 ln L + 2k + 2k(k+1)/(n-k-1).
  auto criterion = [n](double deviance, int k) {
    return n - k - 1 > 0 ? deviance + 2.0 * k + 2.0 * k * (k + 1) / (n - k - 1.0)
                         : std::numeric_limits<double>::infinity();
  };
  s.aicc[0] = criterion(additive.deviance, 1);
  s.aicc[1] = criterion(relative.deviance, 1);
  s.aicc[2] = criterion(combined.deviance, 2);
  s.combined_shape = combined.t;
  const ShapeFit& chosen = kind == NoiseKind::kAdditive ? additive : kind == NoiseKind::kRelative ? relative : combined;
  s.model = modelOf(kind, chosen);
  return s;
}

NoiseSelection selectNoiseModel(const std::vector<double>& e, const std::vector<double>& y) {
  NoiseSelection s = fitNoiseModel(NoiseKind::kCombined, e, y);
  int best = 0;
  for (int k = 1; k < kNumNoiseKinds; ++k)
    if (s.aicc[k] < s.aicc[best]) best = k;
  NoiseSelection chosen = fitNoiseModel(static_cast<NoiseKind>(best), e, y);
  chosen.selected = true;
  return chosen;
}

}  // namespace diagnosis
}  // namespace tread_wear
