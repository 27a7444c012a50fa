#pragma once
/// @file drive_segments.h
/// A wheel's drive cut at its measurement checkpoints (tread depth or mass) into segments, each kept as the
/// operating points the live estimator would integrate, binned into cells (model/point_cells.h), so that a model
/// with any parameters predicts the segment's wear without stepping through the drive again (the mismatch
/// diagnosis of drives, docs/diagnosis.md).
///
/// The steps are those of DriveReplay (drive_replay.h): a grid t_k = start + k / update_rate_hz; before step k
/// every sample with time <= t_k is applied to the wheel's WheelInputs; a step is usable when the required inputs
/// are (requiredInputStatus()); the interval (t_{k-1}, t_k] is integrated when both ends are usable and
/// 0 < dt <= max_step_s. The trapezoid rule of WheelEstimator gives each end of an integrated interval the weight
/// dt / 2, so the replay's loss is sum_k W_r(op_k) V_k w_k and its distance sum_k V_k w_k. Here each end enters
/// the cells of the interval's segment as a WeightedOperatingPoint: the point the model is evaluated at
/// (lowSpeedPoint(): below min_speed_mps W_r is held, so W_r(op) times the true distance V_k w_k is the replay's
/// wear), time w_k, distance V_k w_k. A zero load (wheel off the ground) wears nothing: it adds time and
/// distance to the segment but no point. An interval belongs to the segment of its end time: segment j spans
/// (checkpoint_j, checkpoint_{j+1}].
/// Stretches in which a required input is unusable and no sample arrives are skipped, not stepped through, so a
/// month of drives with days between them costs its driving time only.
/// Not evaluated here: the model. What differs from the replay is only the binning (point_cells.h).

#include <vector>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/point_cells.h"

namespace tread_wear {

/// One wheel's drive between two consecutive checkpoints.
struct DriveSegment {
  double start_s = 0.0, end_s = 0.0;  ///< the checkpoints' times [s]
  double integrated_s = 0.0;          ///< time integrated [s]
  double distance_m = 0.0;            ///< distance integrated, = the sum of the distance weights plus zero-load steps [m]
  double unaccounted_s = 0.0;         ///< time in the segment not integrated [s]
  std::vector<WeightedOperatingPoint> points;  ///< the cells' centroids with their weights (load > 0)
  /// Time-weighted means over the integrated steps [SI]: speed, load, |alpha|, |kappa| and |1/R| (signed means of a
  /// drive cancel between left and right, driving and braking), the tread temperature over the steps that have
  /// one (NaN when less than half of the integrated time has one); and the load's standard deviation [N].
  OperatingPoint mean;
  double load_std_n = 0.0;
};

/// Cuts one wheel's samples into segments (see the file comment).
class DriveSegmenter {
 public:
  /// checkpoints_s: the measurement times [s], increasing, at least two; start_s: the grid's first step [s]
  /// (DriveReplay: the first sample of any wheel). @throw std::invalid_argument naming the problem.
  DriveSegmenter(const ReplaySettings& settings, const PointCellParams& cells, std::vector<double> checkpoints_s,
                 double start_s);
  /// Samples must come in non-decreasing time, none before start_s. @throw std::invalid_argument otherwise
  void addSample(const InputSample& sample);
  /// Runs the steps up to the last checkpoint and returns the segments (one fewer than the checkpoints). Inputs are
  /// held after the last sample until they are stale, as in the node (DriveReplay stops at its last sample).
  std::vector<DriveSegment> finish();

 private:
  struct Accumulator {
    PointCells cells;
    double time_s = 0.0, with_temperature_s = 0.0;
    double sums[7] = {0, 0, 0, 0, 0, 0, 0};  ///< time-weighted: V, |alpha|, |kappa|, |1/R|, Fz, Fz^2, T
    DriveSegment segment;
  };
  void runStepsBefore(double t_s);
  void step(double t_s);
  void addHalfInterval(Accumulator* acc, const OperatingPoint& op, double weight_s);
  int segmentOf(double t_s) const;

  ReplaySettings settings_;
  std::vector<double> checkpoints_s_;
  double start_s_;
  WheelInputs inputs_;
  std::uint64_t next_step_ = 0;
  double last_sample_s_;
  bool prev_usable_ = false;
  double prev_t_s_ = 0.0;
  OperatingPoint prev_op_;
  std::vector<Accumulator> accumulators_;
};

}  // namespace tread_wear
