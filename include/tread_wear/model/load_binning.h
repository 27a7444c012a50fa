#pragma once
/// @file load_binning.h
/// Eq 23: the wear rate of a test run whose vertical load fluctuates, W_r = sum_i beta_i W_r(Fz_i), with the
/// recorded loads grouped into bins of 10 N (paper Section 4.2), beta_i the share of the run in bin i and
/// W_r(Fz_i) the model at the bin centre. Two sources of the shares:
///  - raw load samples: a histogram with edges at multiples of the bin width (as the paper bins recorded data);
///  - a normal distribution N(mean, std) (what a run table's load_mean_n/load_std_n describe): bins centred on
///    the mean, spanning +-span_sigmas standard deviations, shares = normal probabilities renormalised over the
///    bins kept.
/// Loads must stay > 0: bins whose centre is <= 0 are dropped and the rest renormalised.
/// Evaluating at bin centres adds about W_r'' w^2/24 for bin width w (Sheppard): a 10 N bin is coarse next to
/// the few-newton load scatter of the rig, which is why the width is an option.

#include <functional>
#include <string>
#include <vector>

namespace tread_wear {

struct LoadBinningOptions {
  double bin_width_n = 10.0;  ///< bin width [N], > 0 (paper: 10 N)
  double span_sigmas = 4.0;   ///< normal source: bins cover mean +- span_sigmas std [-], > 0

  bool validate(std::string* error) const;
};

struct LoadBin {
  double centre_n;  ///< bin centre load [N]
  double weight;    ///< share beta_i of the run [-]; the weights of a binning sum to 1
};

/// Bins of a normal load distribution. std_n = 0 (or NaN: unknown) gives the single bin {mean_n, 1}.
/// @throw std::invalid_argument for mean_n <= 0, std_n < 0 or invalid options.
std::vector<LoadBin> normalLoadBins(double mean_n, double std_n, const LoadBinningOptions& options = {});
/// Histogram bins [k w, (k+1) w) of recorded loads with their sample shares.
/// @throw std::invalid_argument for no samples, a non-finite or non-positive sample, or invalid options.
std::vector<LoadBin> sampleLoadBins(const std::vector<double>& loads_n, const LoadBinningOptions& options = {});
/// Eq 23: sum of weight * value(centre) over the bins.
double binnedAverage(const std::vector<LoadBin>& bins, const std::function<double(double load_n)>& value);

}  // namespace tread_wear
