#include "tread_wear/planning/wear_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

/// Relative round-off of exp(ln(floor)) - floor: rates below it times the floor are zero wear [-].
constexpr double kFloorRoundOff = 1e-9;


bool strictlyIncreasingFinite(const std::vector<double>& axis) {
  for (std::size_t i = 0; i < axis.size(); ++i) {
    if (!std::isfinite(axis[i])) return false;
    if (i > 0 && !(axis[i] > axis[i - 1])) return false;
  }
  return true;
}

std::string axisText(const std::vector<double>& axis) {
  std::ostringstream s;
  s << "[";
  for (std::size_t i = 0; i < axis.size(); ++i) s << (i ? ", " : "") << axis[i];
  s << "]";
  return s.str();
}

/// Cell of x on an axis: index i with axis[i] <= x <= axis[i + 1] and the fraction t in [0, 1]; false outside.
/// An axis of one node is a single cell of width zero (t = 0).
bool locate(const std::vector<double>& axis, double x, std::size_t* i, double* t) {
  // A node's own value recomputed (a_y = v^2 (a_y / v^2)) may miss the end node by a rounding: still inside.
  const double slack = 1e-12 * (1.0 + std::fabs(axis.front()) + std::fabs(axis.back()));
  if (!(x >= axis.front() - slack && x <= axis.back() + slack)) return false;
  x = std::clamp(x, axis.front(), axis.back());
  if (axis.size() == 1) {
    *i = 0;
    *t = 0.0;
    return true;
  }
  std::size_t cell = static_cast<std::size_t>(std::upper_bound(axis.begin(), axis.end(), x) - axis.begin());
  cell = std::min(std::max<std::size_t>(cell, 1), axis.size() - 1) - 1;
  *i = cell;
  *t = (x - axis[cell]) / (axis[cell + 1] - axis[cell]);
  return true;
}

std::string outside(const char* field, double value, const std::vector<double>& axis, const char* unit) {
  std::ostringstream s;
  s.precision(10);
  s << field << " = " << value << ": outside the map's axis [" << axis.front() << ", " << axis.back() << "] " << unit
    << " (evaluate this trajectory directly)";
  return s.str();
}

}  // namespace

std::vector<double> WearMapParams::uniformAxis(double first, double last, int n) {
  std::vector<double> axis(static_cast<std::size_t>(std::max(n, 1)), first);
  for (int i = 1; i < n; ++i) axis[static_cast<std::size_t>(i)] = first + (last - first) * i / (n - 1);
  return axis;
}

bool WearMapParams::validate(std::string* error) const {
  if (speed_mps.empty() || !strictlyIncreasingFinite(speed_mps) || !(speed_mps.front() > 0.0))
    return failValidation(error, "speed_mps", axisText(speed_mps), "a non-empty, strictly increasing list > 0 [m/s]");
  if (accel_x_mps2.empty() || !strictlyIncreasingFinite(accel_x_mps2))
    return failValidation(error, "accel_x_mps2", axisText(accel_x_mps2),
                          "a non-empty, strictly increasing list [m/s^2]");
  if (lateral_share.empty() || !strictlyIncreasingFinite(lateral_share) || lateral_share.front() < -1.0 ||
      lateral_share.back() > 1.0)
    return failValidation(error, "lateral_share", axisText(lateral_share),
                          "a non-empty, strictly increasing list in [-1, 1]");
  if (!(std::isfinite(max_lateral_accel_mps2) && max_lateral_accel_mps2 > 0.0))
    return failValidation(error, "max_lateral_accel_mps2", max_lateral_accel_mps2, "finite and > 0 [m/s^2]");
  if (!(std::isfinite(wear_floor_kg_per_s) && wear_floor_kg_per_s > 0.0))
    return failValidation(error, "wear_floor_kg_per_s", wear_floor_kg_per_s, "finite and > 0 [kg/s]");
  if (build_threads < 1) return failValidation(error, "build_threads", build_threads, ">= 1");
  return true;
}

WearMap::WearMap(const VehicleWearSetup& setup, const WearMapParams& params) : setup_(setup), params_(params) {}

std::shared_ptr<const WearMap> WearMap::build(const VehicleWearSetup& setup, const WearMapParams& params,
                                              const std::atomic<bool>* cancel) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  if (!setup.validate(&error)) throw std::invalid_argument("invalid vehicle wear setup: " + error);
  if (!params.validate(&error)) throw std::invalid_argument("invalid wear map parameters: " + error);
  std::shared_ptr<WearMap> map(new WearMap(setup, params));
  const std::size_t n_v = params.speed_mps.size(), n_ax = params.accel_x_mps2.size();
  const std::size_t n_ay = params.lateral_share.size();
  map->nodes_ = n_v * n_ax * n_ay;
  map->values_.assign(map->nodes_ * kValuesPerNode, 0.0);
  map->fingerprint_ = setupFingerprint(setup);

  // Rows of (speed, a_x) go to the threads in turn; each thread has its own models (WearModel is not thread-safe).
  std::atomic<std::size_t> next_row{0};
  std::mutex failure_mutex;
  std::string failure;
  const auto work = [&]() {
    try {
      const TrajectoryCostEvaluator direct(setup);
      WheelRates rates;
      std::string why;
      for (std::size_t row = next_row++; row < n_v * n_ax; row = next_row++) {
        if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return;
        const double v = params.speed_mps[row / n_ax];
        const double a_x = params.accel_x_mps2[row % n_ax];
        for (std::size_t k = 0; k < n_ay; ++k) {
          const double kappa = map->nodeCurvature_per_m(row / n_ax, k);
          if (!direct.rates({0.0, v, a_x, kappa}, &rates, &why)) {
            std::ostringstream msg;
            msg << "wear map node (speed_mps " << v << ", accel_x_mps2 " << a_x << ", lateral_share "
                << params.lateral_share[k] << "): " << why;
            throw std::runtime_error(msg.str());
          }
          double* node = &map->values_[(row * n_ay + k) * kValuesPerNode];
          for (std::size_t w = 0; w < kWheelCount; ++w) {
            node[w] = std::log(rates.wear_kg_per_s[w] + params.wear_floor_kg_per_s);
            node[kWheelCount + w] = rates.stick_fraction[w];
          }
        }
      }
    } catch (const std::exception& e) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (failure.empty()) failure = e.what();
      next_row = n_v * n_ax;  // the others stop at their next row
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < params.build_threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& t : helpers) t.join();
  if (!failure.empty()) throw std::runtime_error(failure);
  if (cancel != nullptr && cancel->load()) return nullptr;
  map->build_time_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return map;
}

double WearMap::maxLateralAccel_mps2(double speed_mps) const {
  return std::min(params_.max_lateral_accel_mps2, setup_.max_path_curvature_per_m * speed_mps * speed_mps);
}

double WearMap::lateralShare(double speed_mps, double path_curvature_per_m) const {
  const double kappa_max = setup_.max_path_curvature_per_m;
  // Below the speed where kappa_max reaches the lateral limit the share is kappa / kappa_max (no division by v).
  if (kappa_max * speed_mps * speed_mps <= params_.max_lateral_accel_mps2) return path_curvature_per_m / kappa_max;
  return speed_mps * speed_mps * path_curvature_per_m / params_.max_lateral_accel_mps2;
}

double WearMap::nodeCurvature_per_m(std::size_t i, std::size_t k) const {
  const double v = params_.speed_mps[i];
  return params_.lateral_share[k] * maxLateralAccel_mps2(v) / (v * v);
}

double WearMap::nodeWearRate_kg_per_s(int wheel, std::size_t node) const {
  return std::max(0.0, std::exp(values_[node * kValuesPerNode + static_cast<std::size_t>(wheel)]) -
                           params_.wear_floor_kg_per_s);
}

bool WearMap::rates(const TrajectorySample& sample, WheelRates* rates, std::string* error) const {
  const double v = sample.speed_mps;
  if (sample.grade_rad != 0.0) {
    if (error != nullptr) {
      std::ostringstream s;
      s.precision(10);
      s << "grade_rad = " << sample.grade_rad << ": the map is for a flat road (evaluate this trajectory directly)";
      *error = s.str();
    }
    return false;
  }
  if (v > params_.speed_mps.back()) {
    if (error != nullptr) *error = outside("speed_mps", v, params_.speed_mps, "[m/s]");
    return false;
  }
  std::size_t i = 0, j = 0, k = 0;
  double tv = 0.0, tx = 0.0, ty = 0.0;
  // Below the first speed node the rates are the node's times v / v_0 (file comment).
  const double v_node = std::max(v, params_.speed_mps.front());
  locate(params_.speed_mps, v_node, &i, &tv);
  if (!locate(params_.accel_x_mps2, sample.accel_mps2, &j, &tx)) {
    if (error != nullptr) *error = outside("accel_mps2", sample.accel_mps2, params_.accel_x_mps2, "[m/s^2]");
    return false;
  }
  const double share = lateralShare(v, sample.path_curvature_per_m);
  if (!locate(params_.lateral_share, share, &k, &ty)) {
    if (error != nullptr) {
      std::ostringstream s;
      s.precision(10);
      s << "lateral acceleration v^2 kappa = " << v * v * sample.path_curvature_per_m << " [m/s^2]: outside the map's "
        << "reach, lateral_share " << share << " not in [" << params_.lateral_share.front() << ", "
        << params_.lateral_share.back() << "] of min(max_lateral_accel_mps2 = " << params_.max_lateral_accel_mps2
        << ", max_path_curvature_per_m v^2) (evaluate this trajectory directly)";
      *error = s.str();
    }
    return false;
  }
  // A one-node axis has no upper neighbour: its step is 0 (t is 0 there too).
  const std::size_t n_ax = params_.accel_x_mps2.size(), n_ay = params_.lateral_share.size();
  const std::size_t di = params_.speed_mps.size() > 1 ? n_ax * n_ay : 0, dj = n_ax > 1 ? n_ay : 0;
  const std::size_t dk = n_ay > 1 ? 1 : 0;
  const std::size_t base = nodeIndex(i, j, k);
  const std::size_t corner[8] = {base,      base + dk,      base + dj,      base + dj + dk,
                                 base + di, base + di + dk, base + di + dj, base + di + dj + dk};
  const double weight[8] = {(1 - tv) * (1 - tx) * (1 - ty), (1 - tv) * (1 - tx) * ty, (1 - tv) * tx * (1 - ty),
                            (1 - tv) * tx * ty,             tv * (1 - tx) * (1 - ty), tv * (1 - tx) * ty,
                            tv * tx * (1 - ty),             tv * tx * ty};
  double mixed[kValuesPerNode] = {};
  for (int c = 0; c < 8; ++c) {
    const double* node = &values_[corner[c] * kValuesPerNode];
    for (std::size_t q = 0; q < kValuesPerNode; ++q) mixed[q] += weight[c] * node[q];
  }
  const double below_first = v / v_node;  // 1 from the first node up
  for (std::size_t w = 0; w < kWheelCount; ++w) {
    // A node that wears nothing (w4 = 0: pure stick) comes back as the floor's round-off, not as 0.
    const double above_floor = std::exp(mixed[w]) - params_.wear_floor_kg_per_s;
    rates->wear_kg_per_s[w] =
        above_floor > kFloorRoundOff * params_.wear_floor_kg_per_s ? above_floor * below_first : 0.0;
    rates->stick_fraction[w] = mixed[kWheelCount + w];
  }
  return true;
}

}  // namespace tread_wear
