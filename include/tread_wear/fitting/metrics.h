#pragma once
/// @file metrics.h
/// Goodness-of-fit measures of the paper: RMSE (Eq 21), RMSER (Eq 24), R^2 (Eq 4), RSD (Eq 5) and the
/// Error Ratio Index ERI (Section 4.2: RMSER of a model relative to a reference model's RMSER).
/// Inputs are paired measured/predicted values; every function throws std::invalid_argument for empty input,
/// mismatched sizes or non-finite values (callers drop unmeasured points first).

#include <vector>

namespace tread_wear {

/// Eq 21: sqrt(mean((predicted - measured)^2)), in the unit of the data.
double rmse(const std::vector<double>& measured, const std::vector<double>& predicted);
/// Eq 24: y_i = predicted_i / measured_i - 1 per point. Throws when a measured value is 0.
std::vector<double> errorRatios(const std::vector<double>& measured, const std::vector<double>& predicted);
/// Eq 24: sqrt(mean(y_i^2)) as a fraction (0.0832 = 8.32%). Throws when a measured value is 0.
double rmser(const std::vector<double>& measured, const std::vector<double>& predicted);
/// Eq 4: 1 - sum((x_i - xhat_i)^2) / sum((x_i - mean(x))^2). Throws when all measured values are equal.
double rSquared(const std::vector<double>& measured, const std::vector<double>& predicted);
/// Eq 5, population form as printed: sqrt(mean((x_i/mean(x) - 1)^2)) as a fraction. Throws when mean(x) = 0.
double relativeStandardDeviation(const std::vector<double>& samples);
/// ERI: rmser_model / rmser_reference (Table 5 uses the model Opt as the reference). Throws unless the
/// reference is > 0 and both are finite.
double errorRatioIndex(double rmser_model, double rmser_reference);

}  // namespace tread_wear
