#include "tread_wear/fitting/metrics.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tread_wear {
namespace {

void checkFinite(const std::vector<double>& values, const char* what) {
  if (values.empty()) throw std::invalid_argument(std::string(what) + ": no values");
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw std::invalid_argument(std::string(what) + "[" + std::to_string(i) + "] is not finite");
}

void checkPairs(const std::vector<double>& measured, const std::vector<double>& predicted) {
  checkFinite(measured, "measured");
  checkFinite(predicted, "predicted");
  if (measured.size() != predicted.size())
    throw std::invalid_argument("measured has " + std::to_string(measured.size()) + " values, predicted " +
                                std::to_string(predicted.size()));
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

double rootMeanSquare(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v * v;
  return std::sqrt(sum / static_cast<double>(values.size()));
}

}  // namespace

double rmse(const std::vector<double>& measured, const std::vector<double>& predicted) {
  checkPairs(measured, predicted);
  std::vector<double> residuals(measured.size());
  for (std::size_t i = 0; i < measured.size(); ++i) residuals[i] = predicted[i] - measured[i];
  return rootMeanSquare(residuals);
}

std::vector<double> errorRatios(const std::vector<double>& measured, const std::vector<double>& predicted) {
  checkPairs(measured, predicted);
  std::vector<double> ratios(measured.size());
  for (std::size_t i = 0; i < measured.size(); ++i) {
    if (measured[i] == 0.0)
      throw std::invalid_argument("measured[" + std::to_string(i) + "] = 0: the error ratio is undefined");
    ratios[i] = predicted[i] / measured[i] - 1.0;
  }
  return ratios;
}

double rmser(const std::vector<double>& measured, const std::vector<double>& predicted) {
  return rootMeanSquare(errorRatios(measured, predicted));
}

double rSquared(const std::vector<double>& measured, const std::vector<double>& predicted) {
  checkPairs(measured, predicted);
  const double m = mean(measured);
  double residual = 0.0;
  double total = 0.0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    residual += (measured[i] - predicted[i]) * (measured[i] - predicted[i]);
    total += (measured[i] - m) * (measured[i] - m);
  }
  if (total == 0.0) throw std::invalid_argument("R^2 is undefined when all measured values are equal");
  return 1.0 - residual / total;
}

double relativeStandardDeviation(const std::vector<double>& samples) {
  checkFinite(samples, "samples");
  const double m = mean(samples);
  if (m == 0.0) throw std::invalid_argument("RSD is undefined for a zero mean");
  std::vector<double> deviations(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) deviations[i] = samples[i] / m - 1.0;
  return rootMeanSquare(deviations);
}

double errorRatioIndex(double rmser_model, double rmser_reference) {
  if (!std::isfinite(rmser_model) || !std::isfinite(rmser_reference) || !(rmser_reference > 0.0))
    throw std::invalid_argument("ERI needs finite RMSERs and a reference RMSER > 0");
  return rmser_model / rmser_reference;
}

}  // namespace tread_wear
