#pragma once
/// @file point_cells.h
/// Compression of the operating points of a drive into cells, so that a drive of a month (tens of millions of
/// steps) is predicted from a few thousand model evaluations (estimation/drive_segments.h, the mismatch
/// diagnosis of drives).
///
/// A drive's wear is sum_k W_r(op_k) d_k over its steps (WeightedOperatingPoint). The points are binned in the
/// coordinates (Fz, alpha, kappa, V, 1/R, T), each on the scale u = asinh(x / scale) / width: linear within
/// +-scale of zero, logarithmic (relative width `width`) beyond, so small slips get the same relative resolution
/// as large ones (W_r grows faster than linearly in slip). A cell holds the sums of its points' time and distance
/// weights and its centroid, the distance-weighted mean of each coordinate (time-weighted when the cell has no
/// distance). Replacing a cell's points by the centroid keeps the integrals of time and distance exactly and the
/// wear to second order in the cell width for a W_r that is smooth in the cell: sum_k W_r(op_k) d_k =
/// W_r(centroid) d + O(width^2 W_r'' spread). Tread temperature NaN (unknown) is a bin of its own.
/// Measured against the replay, which evaluates every step: docs/diagnosis.md, "Drives between measurements".

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "tread_wear/model/operating_point.h"

namespace tread_wear {

/// Bin of one coordinate: u = asinh(x / scale) / width.
struct CellAxis {
  double scale;  ///< below it the bins are linear [unit of the coordinate], > 0
  double width;  ///< bin width in asinh units: the relative width beyond the scale [-], >= 1e-6
};

/// Resolution of the cells. Defaults: 2% in load, 4% in |alpha| and |kappa| above 1e-3, 4% in speed above
/// 1 m/s, 10% in |1/R| above 1e-3 1/m, 1 degC in tread temperature.
struct PointCellParams {
  CellAxis load{100.0, 0.02};            ///< Fz [N]
  CellAxis slip_angle{1e-3, 0.04};       ///< alpha [rad]
  CellAxis slip_ratio{1e-3, 0.04};       ///< kappa [-]
  CellAxis speed{1.0, 0.04};             ///< V [m/s]
  CellAxis path_curvature{1e-3, 0.1};    ///< 1/R [1/m]
  double temperature_bin_c = 1.0;        ///< tread temperature bin [degC], >= 1e-6

  /// Names the first field that is not finite and > 0 (scales) or >= 1e-6 (widths, temperature bin).
  bool validate(std::string* error) const;
};

/// Points binned into cells (see the file comment).
class PointCells {
 public:
  /// @throw std::invalid_argument naming the field for invalid params.
  explicit PointCells(const PointCellParams& params = PointCellParams());

  /// Adds a point; returns the index of its cell (cells are numbered in the order they first receive a point).
  /// Points with no weight are ignored (returns -1).
  int add(const WeightedOperatingPoint& point);
  /// The cells as weighted points: each cell's summed weights at its centroid.
  std::vector<WeightedOperatingPoint> points() const;

 private:
  using Key = std::array<std::int32_t, 6>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  struct Cell {
    double time_s = 0.0, distance_m = 0.0;
    std::array<double, 6> time_sum{}, distance_sum{};  ///< weighted sums of the coordinates
    bool temperature_known = false;
  };
  Key key(const OperatingPoint& op) const;

  PointCellParams params_;
  std::unordered_map<Key, int, KeyHash> index_;
  std::vector<Cell> cells_;
};

}  // namespace tread_wear
