#pragma once
/// @file noise_model.h
/// The measurement noise model of one output of the mismatch diagnosis (issue 26, part 0b): the standard deviation
/// of a measured value y as a function of its level,
///   additive   sigma = a                      (a transducer's zero noise, e.g. 1 N on the side force)
///   relative   sigma = b |y|                  (a scatter that scales with the value, e.g. wear repeats)
///   combined   sigma = sqrt(a^2 + b^2 y^2)    (both)
/// The diagnosis weights a residual predicted - measured by 1/sigma(measured); for `relative` that is the error
/// ratio of Eq 24 divided by b, the weighting the diagnosis had before this model was estimated.
///
/// Selection (selectNoiseModel): maximum likelihood of deviations e_i ~ N(0, sigma(y_i)^2) under each model, and the
/// lowest AICc (Hurvich and Tsai 1989; k = 1 for additive and relative, 2 for combined). The combined model is
/// profiled over its shape: sigma_i^2 = c ((1 - t) m2 + t y_i^2), m2 the mean of y^2, t in [0, 1] on a grid of 201
/// points, c in closed form (the mean of e_i^2 / ((1 - t) m2 + t y_i^2)); t = 0 is additive, t = 1 relative. The
/// deviations are the repeats' (each run minus its condition's mean, scaled by sqrt(n/(n-1)) so that its variance
/// is sigma^2) when the recordings have enough repeats over a range of levels (kMinRepeatDof degrees of freedom,
/// levels spanning a factor kMinLevelSpan), else the base model's residuals.
/// Limits: a residual that carries a model mismatch inflates the variance where the mismatch is; with repeats the
/// condition means absorb it.

#include <string>
#include <vector>

namespace tread_wear {
namespace diagnosis {

enum class NoiseKind { kAdditive = 0, kRelative = 1, kCombined = 2 };
constexpr int kNumNoiseKinds = 3;
/// "additive", "relative" or "combined".
const char* noiseKindName(NoiseKind kind);
/// Parses a noise kind; false (and *kind untouched) for an unknown name.
bool parseNoiseKind(const std::string& name, NoiseKind* kind);
/// "additive, relative, combined or auto", for messages that list the choices of an option.
inline constexpr const char* kNoiseModelChoices = "auto, additive, relative or combined";

/// Fewest degrees of freedom of the repeats, and the smallest ratio of the largest to the smallest repeated level,
/// for the noise model to be selected on the repeats instead of the residuals.
constexpr int kMinRepeatDof = 8;
constexpr double kMinLevelSpan = 1.5;

struct NoiseModel {
  NoiseKind kind = NoiseKind::kRelative;
  double additive = 0.0;  ///< a [unit of the output], >= 0
  double relative = 0.0;  ///< b [-], >= 0

  /// sigma at the measured level y [unit of the output].
  double sigma(double y) const;
  /// The same model scaled to a new size (a and b times factor).
  NoiseModel scaled(double factor) const;
  bool validate(std::string* error) const;
};

struct NoiseSelection {
  NoiseModel model;                 ///< the selected model, at its maximum-likelihood size
  bool selected = false;            ///< chosen by AICc (false: given by the user)
  std::string source;               ///< "repeats (k dof)" or "base-model residuals (n values)"
  double aicc[kNumNoiseKinds] = {0.0, 0.0, 0.0};  ///< of each model on the deviations [-]
  double combined_shape = 0.0;      ///< t of the best combined model [-]
  int values = 0;                   ///< deviations used
};

/// Selects the noise model of deviations e (unit of the output) at levels y (same size, y != 0).
/// @throw std::invalid_argument for sizes that differ or fewer than 3 deviations.
NoiseSelection selectNoiseModel(const std::vector<double>& deviations, const std::vector<double>& levels);
/// The maximum-likelihood size of a given kind on the deviations (the combined one at its best shape).
NoiseSelection fitNoiseModel(NoiseKind kind, const std::vector<double>& deviations, const std::vector<double>& levels);

}  // namespace diagnosis
}  // namespace tread_wear
