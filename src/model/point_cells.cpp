#include "tread_wear/model/point_cells.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "tread_wear/model/validation.h"

namespace tread_wear {
namespace {

/// asinh of any double is below 711, and a tread temperature below 1e3 degC: indices stay within 32 bits.
constexpr double kMinCellWidth = 1e-6;

std::int32_t bin(double x, const CellAxis& axis) {
  return static_cast<std::int32_t>(std::floor(std::asinh(x / axis.scale) / axis.width));
}

std::array<double, 6> coordinates(const OperatingPoint& op) {
  return {op.load_n, op.slip_angle_rad, op.slip_ratio, op.speed_mps, op.path_curvature_per_m,
          std::isfinite(op.tread_temperature_c) ? op.tread_temperature_c : 0.0};
}

bool checkAxis(std::string* error, const std::string& name, const CellAxis& axis) {
  if (!(axis.scale > 0.0) || !std::isfinite(axis.scale))
    return failValidation(error, name + ".scale", axis.scale, "finite and > 0");
  if (!(axis.width >= kMinCellWidth) || !std::isfinite(axis.width))
    return failValidation(error, name + ".width", axis.width, "finite and >= 1e-6 (bin indices are 32-bit)");
  return true;
}

}  // namespace

bool PointCellParams::validate(std::string* error) const {
  if (!checkAxis(error, "load", load) || !checkAxis(error, "slip_angle", slip_angle) ||
      !checkAxis(error, "slip_ratio", slip_ratio) || !checkAxis(error, "speed", speed) ||
      !checkAxis(error, "path_curvature", path_curvature))
    return false;
  if (!(temperature_bin_c >= kMinCellWidth) || !std::isfinite(temperature_bin_c))
    return failValidation(error, "temperature_bin_c", temperature_bin_c, "finite and >= 1e-6 (bin indices are 32-bit)");
  return true;
}

PointCells::PointCells(const PointCellParams& params) : params_(params) {
  std::string error;
  if (!params_.validate(&error)) throw std::invalid_argument("point cells: " + error);
}

std::size_t PointCells::KeyHash::operator()(const Key& k) const {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the six bin indices
  for (std::int32_t v : k) {
    h ^= static_cast<std::uint32_t>(v);
    h *= 1099511628211ull;
  }
  return static_cast<std::size_t>(h);
}

PointCells::Key PointCells::key(const OperatingPoint& op) const {
  const double t = op.tread_temperature_c;
  return {bin(op.load_n, params_.load),
          bin(op.slip_angle_rad, params_.slip_angle),
          bin(op.slip_ratio, params_.slip_ratio),
          bin(op.speed_mps, params_.speed),
          bin(op.path_curvature_per_m, params_.path_curvature),
          std::isfinite(t) ? static_cast<std::int32_t>(std::floor(t / params_.temperature_bin_c))
                           : std::numeric_limits<std::int32_t>::min()};
}

int PointCells::add(const WeightedOperatingPoint& point) {
  if (!(point.time_s > 0.0) && !(point.distance_m > 0.0)) return -1;
  const auto [it, inserted] = index_.emplace(key(point.op), static_cast<int>(cells_.size()));
  if (inserted) cells_.emplace_back();
  Cell& c = cells_[static_cast<std::size_t>(it->second)];
  const std::array<double, 6> x = coordinates(point.op);
  c.time_s += point.time_s;
  c.distance_m += point.distance_m;
  for (int j = 0; j < 6; ++j) {
    c.time_sum[j] += point.time_s * x[j];
    c.distance_sum[j] += point.distance_m * x[j];
  }
  c.temperature_known = std::isfinite(point.op.tread_temperature_c);
  return it->second;
}

std::vector<WeightedOperatingPoint> PointCells::points() const {
  std::vector<WeightedOperatingPoint> out;
  out.reserve(cells_.size());
  for (const Cell& c : cells_) {
    const bool by_distance = c.distance_m > 0.0;
    const std::array<double, 6>& sum = by_distance ? c.distance_sum : c.time_sum;
    const double w = by_distance ? c.distance_m : c.time_s;
    WeightedOperatingPoint p;
    p.op.load_n = sum[0] / w;
    p.op.slip_angle_rad = sum[1] / w;
    p.op.slip_ratio = sum[2] / w;
    p.op.speed_mps = sum[3] / w;
    p.op.path_curvature_per_m = sum[4] / w;
    p.op.tread_temperature_c = c.temperature_known ? sum[5] / w : std::numeric_limits<double>::quiet_NaN();
    p.time_s = c.time_s;
    p.distance_m = c.distance_m;
    out.push_back(p);
  }
  return out;
}

}  // namespace tread_wear
