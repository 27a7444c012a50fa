#include "tread_wear/estimation/drive_segments.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tread_wear {

DriveSegmenter::DriveSegmenter(const ReplaySettings& settings, const PointCellParams& cells,
                               std::vector<double> checkpoints_s, double start_s)
    : settings_(settings),
      checkpoints_s_(std::move(checkpoints_s)),
      start_s_(start_s),
      inputs_(settings.estimator.limits),
      last_sample_s_(start_s) {
  std::string error;
  if (!settings_.validate(&error)) throw std::invalid_argument("drive segments: " + error);
  if (!std::isfinite(start_s_)) throw std::invalid_argument("drive segments: start_s is not finite");
  if (checkpoints_s_.size() < 2)
    throw std::invalid_argument("drive segments: " + std::to_string(checkpoints_s_.size()) +
                                " checkpoints, at least 2 needed for a segment");
  for (std::size_t i = 0; i < checkpoints_s_.size(); ++i) {
    if (!std::isfinite(checkpoints_s_[i]) || (i > 0 && !(checkpoints_s_[i] > checkpoints_s_[i - 1])))
      throw std::invalid_argument("drive segments: checkpoint " + std::to_string(i + 1) + " at t = " +
                                  std::to_string(checkpoints_s_[i]) + " s is not after the one before it");
  }
  for (std::size_t i = 0; i + 1 < checkpoints_s_.size(); ++i) {
    accumulators_.push_back(Accumulator{PointCells(cells), 0.0, 0.0, {}, DriveSegment{}});
    accumulators_.back().segment.start_s = checkpoints_s_[i];
    accumulators_.back().segment.end_s = checkpoints_s_[i + 1];
  }
}

int DriveSegmenter::segmentOf(double t_s) const {
  if (!(t_s > checkpoints_s_.front()) || t_s > checkpoints_s_.back()) return -1;
  // The segment j with checkpoint_j < t <= checkpoint_{j+1}.
  const auto it = std::lower_bound(checkpoints_s_.begin(), checkpoints_s_.end(), t_s);
  return static_cast<int>(it - checkpoints_s_.begin()) - 1;
}

void DriveSegmenter::addSample(const InputSample& sample) {
  if (!(sample.t_s >= last_sample_s_ - kInputStampTolerance_s))
    throw std::invalid_argument("drive segments: sample at t = " + std::to_string(sample.t_s) +
                                " s comes before the previous one (" + std::to_string(last_sample_s_) + " s)");
  runStepsBefore(sample.t_s);
  inputs_.apply(sample);
  last_sample_s_ = std::max(last_sample_s_, sample.t_s);
}

void DriveSegmenter::runStepsBefore(double t_s) {
  const double rate = settings_.update_rate_hz;
  // Step k runs once every sample with time <= t_k has been applied: here, for t_k < t_s.
  while (true) {
    const double t_k = start_s_ + static_cast<double>(next_step_) / rate;
    if (!(t_k + kInputStampTolerance_s < t_s) || t_k > checkpoints_s_.back()) return;
    step(t_k);
    ++next_step_;
    if (!prev_usable_) {
      // Without a new sample an unusable input stays unusable: skip to the first step that can see the next one.
      const double k_next = std::ceil((t_s - kInputStampTolerance_s - start_s_) * rate - 1e-9);
      next_step_ = std::max(next_step_, static_cast<std::uint64_t>(std::max(0.0, k_next)));
    }
  }
}

void DriveSegmenter::step(double t_s) {
  const WheelStatus status = requiredInputStatus(inputs_, t_s, settings_.estimator.stale_timeout_s);
  OperatingPoint op = operatingPoint(inputs_, t_s, settings_.estimator.stale_timeout_s);
  const bool usable = status == WheelStatus::kOk && (op.load_n == 0.0 || op.validate(nullptr));
  const double dt = t_s - prev_t_s_;
  if (usable && prev_usable_ && dt > 0.0 && dt <= settings_.estimator.max_step_s) {
    const int s = segmentOf(t_s);
    if (s >= 0) {
      Accumulator& acc = accumulators_[static_cast<std::size_t>(s)];
      addHalfInterval(&acc, prev_op_, 0.5 * dt);
      addHalfInterval(&acc, op, 0.5 * dt);
      acc.segment.integrated_s += dt;
    }
  }
  prev_usable_ = usable;
  prev_t_s_ = t_s;
  prev_op_ = op;
}

void DriveSegmenter::addHalfInterval(Accumulator* acc, const OperatingPoint& op, double weight_s) {
  const double distance_m = op.speed_mps * weight_s;
  acc->segment.distance_m += distance_m;
  acc->time_s += weight_s;
  const double x[7] = {op.speed_mps, std::abs(op.slip_angle_rad), std::abs(op.slip_ratio),
                       std::abs(op.path_curvature_per_m), op.load_n, op.load_n * op.load_n, op.tread_temperature_c};
  for (int j = 0; j < 6; ++j) acc->sums[j] += weight_s * x[j];
  if (std::isfinite(op.tread_temperature_c)) {
    acc->sums[6] += weight_s * op.tread_temperature_c;
    acc->with_temperature_s += weight_s;
  }
  if (op.load_n > 0.0) acc->cells.add({lowSpeedPoint(op, settings_.model), weight_s, distance_m});
}

std::vector<DriveSegment> DriveSegmenter::finish() {
  runStepsBefore(std::nextafter(checkpoints_s_.back() + kInputStampTolerance_s, INFINITY));
  std::vector<DriveSegment> out;
  for (Accumulator& acc : accumulators_) {
    DriveSegment s = acc.segment;
    s.unaccounted_s = std::max(0.0, s.end_s - s.start_s - s.integrated_s);
    s.points = acc.cells.points();
    if (acc.time_s > 0.0) {
      const double* m = acc.sums;
      s.mean.speed_mps = m[0] / acc.time_s;
      s.mean.slip_angle_rad = m[1] / acc.time_s;
      s.mean.slip_ratio = m[2] / acc.time_s;
      s.mean.path_curvature_per_m = m[3] / acc.time_s;
      s.mean.load_n = m[4] / acc.time_s;
      s.load_std_n = std::sqrt(std::max(0.0, m[5] / acc.time_s - s.mean.load_n * s.mean.load_n));
      s.mean.tread_temperature_c =
          acc.with_temperature_s > 0.5 * acc.time_s ? m[6] / acc.with_temperature_s : std::nan("");
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace tread_wear
