#include "tread_wear/model/load_binning.h"

#include <cmath>
#include <map>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

void requireValid(const LoadBinningOptions& options) {
  std::string error;
  if (!options.validate(&error)) throw std::invalid_argument("load binning: " + error);
}

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

void normalise(std::vector<LoadBin>* bins) {
  double total = 0.0;
  for (const LoadBin& b : *bins) total += b.weight;
  for (LoadBin& b : *bins) b.weight /= total;
}

}  // namespace

bool LoadBinningOptions::validate(std::string* error) const {
  if (!(std::isfinite(bin_width_n) && bin_width_n > 0.0))
    return failValidation(error, "bin_width_n", bin_width_n, "finite and > 0");
  if (!(std::isfinite(span_sigmas) && span_sigmas > 0.0))
    return failValidation(error, "span_sigmas", span_sigmas, "finite and > 0");
  return true;
}

std::vector<LoadBin> normalLoadBins(double mean_n, double std_n, const LoadBinningOptions& options) {
  requireValid(options);
  if (!(std::isfinite(mean_n) && mean_n > 0.0))
    throw std::invalid_argument("load mean = " + std::to_string(mean_n) + " N: must be > 0");
  if (std::isnan(std_n) || std_n == 0.0) return {{mean_n, 1.0}};
  if (!(std::isfinite(std_n) && std_n > 0.0))
    throw std::invalid_argument("load std = " + std::to_string(std_n) + " N: must be >= 0");
  const double w = options.bin_width_n;
  // Bins centred on the mean, symmetric, the outermost reaching past mean +- span_sigmas std.
  const int half_count = static_cast<int>(std::ceil((options.span_sigmas * std_n - 0.5 * w) / w));
  std::vector<LoadBin> bins;
  for (int i = -std::max(half_count, 0); i <= std::max(half_count, 0); ++i) {
    const double centre = mean_n + i * w;
    if (centre <= 0.0) continue;
    const double p = normalCdf((centre + 0.5 * w - mean_n) / std_n) - normalCdf((centre - 0.5 * w - mean_n) / std_n);
    bins.push_back({centre, p});
  }
  normalise(&bins);
  return bins;
}

std::vector<LoadBin> sampleLoadBins(const std::vector<double>& loads_n, const LoadBinningOptions& options) {
  requireValid(options);
  if (loads_n.empty()) throw std::invalid_argument("load samples: none given");
  std::map<long, int> counts;
  for (std::size_t i = 0; i < loads_n.size(); ++i) {
    if (!(std::isfinite(loads_n[i]) && loads_n[i] > 0.0))
      throw std::invalid_argument("load sample " + std::to_string(i) + " = " + std::to_string(loads_n[i]) +
                                  " N: must be finite and > 0");
    ++counts[static_cast<long>(std::floor(loads_n[i] / options.bin_width_n))];
  }
  std::vector<LoadBin> bins;
  for (const auto& [index, count] : counts)
    bins.push_back({(index + 0.5) * options.bin_width_n, static_cast<double>(count) / loads_n.size()});
  return bins;
}

double binnedAverage(const std::vector<LoadBin>& bins, const std::function<double(double)>& value) {
  double sum = 0.0;
  for (const LoadBin& b : bins) sum += b.weight * value(b.centre_n);
  return sum;
}

}  // namespace tread_wear
