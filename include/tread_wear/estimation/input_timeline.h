#pragma once
/// @file input_timeline.h
/// One wheel's input samples put back in stamp order and released on a fixed step grid, so that a wheel stepped on
/// its inputs' own stamps (tread_wear_node under simulated time: a replayed bag) sees what the offline replay
/// (drive_replay.h) sees, whatever order and bursts the samples arrive in.
///
/// Why: each input topic reaches the node over its own connection. At a fast replay (a bag at 50x) and on a busy
/// machine one input runs tens of milliseconds of wall time, i.e. seconds of bag time, behind the others; a wheel
/// that steps on the latest sample of each input would then read the lagging one as stale and lose that time.
///
/// Rule, in the pattern of a message_filters cache and robot_localization's measurement queue:
///   - each input keeps its samples in arrival order (one connection delivers in order) in a ring of fixed capacity;
///   - the grid is t_k = t_0 + k step_s, t_0 the earliest buffered stamp when the first step is released (again after
///     a restart());
///   - step t_k is released once every gating input has a sample stamped at or after t_k (the required inputs always,
///     the tread temperature once it has arrived): then every buffered sample stamped <= t_k is applied to the wheel's
///     WheelInputs, in order per input, exactly as DriveReplay applies them before its step t_k;
///   - an input seen lagging the newest sample by more than max_lead_s (or not yet seen) at every arrival for wait_s
///     of wall time is no longer waited for: steps are released up to max_lead_s behind the newest sample, and
///     WheelEstimator reads that input as stale there (lost, counted, reported), never as a silent hold. Lagging is
///     judged at arrivals, so a node that was not running (descheduled on a busy machine) did not see anything lag;
///     and the samples of one topic often arrive in runs of many (one connection per topic, read in chunks), so the
///     wait is in wall time, not in stamps;
///   - a full ring forces the next step (flush), never a dropped sample.
/// Allocates only at construction; push() and nextStep() are O(1) per sample. Not thread-safe (the caller locks).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tread_wear/estimation/wheel_estimator.h"

namespace tread_wear {

struct InputTimelineParams {
  /// stamp lead of the newest sample beyond which a silent input is no longer waited for [s], > 0 (the node: its
  /// max_step_s)
  double max_lead_s = 1.0;
  double wait_s = 2.0;      ///< wall time a lagging input is waited for [s], >= 0
  std::size_t capacity = 8192;  ///< samples buffered per input [-], >= 2

  bool validate(std::string* error) const;
};

class InputTimeline {
 public:
  /// @throw std::invalid_argument naming the field for invalid params
  explicit InputTimeline(const InputTimelineParams& params = InputTimelineParams());

  enum class Push : std::uint8_t {
    kTaken = 0,     ///< buffered
    kFull = 1,      ///< the input's ring is full: release a step with flush (nextStep) and push again
    kBackward = 2   ///< stamped before the input's previous sample (a looping bag): flush all, restart(), push again
  };
  /// Buffers a sample that arrived at wall time wall_s [s] (a steady clock).
  Push push(const InputSample& sample, double wall_s);

  /// The next step due at wall time wall_s [s] on a grid of step_s [s] (> 0): applies the buffered samples stamped up
  /// to it to *inputs, sets *t_s and returns true; false when no step is due. flush: release steps up to the newest
  /// sample without waiting for lagging inputs (a full ring, a backward jump).
  bool nextStep(double wall_s, double step_s, bool flush, WheelInputs* inputs, double* t_s);

  /// Forgets the grid, the inputs' last stamps and what is still buffered (after a flush at a backward jump): the
  /// next samples start a new grid.
  void restart();

  std::size_t buffered(InputKind kind) const { return rings_[static_cast<int>(kind)].size; }
  /// Steps released past an input that was no longer waited for, or by a flush [-].
  std::uint64_t stepsPastLaggingInput() const { return steps_past_lagging_; }
  /// Pushes that found a full ring [-].
  std::uint64_t fullRings() const { return full_rings_; }

 private:
  struct Ring {
    std::vector<InputSample> samples;  ///< capacity slots
    std::size_t head = 0, size = 0;
    bool arrived = false;     ///< a sample arrived since construction or restart()
    double last_stamp_s = 0.0;  ///< stamp of the latest sample pushed [s]
    bool lagging = false;       ///< gating and more than max_lead_s behind the newest sample (or never arrived)
    double lagging_since_wall_s = 0.0;  ///< wall time of the arrival that first saw it lagging [s]
  };
  bool gating(InputKind kind) const;
  /// The latest grid time whose samples have all arrived (or are no longer waited for) [s]; *forced when that took
  /// giving up on a lagging input or a flush.
  double horizon_s(double wall_s, bool flush, bool* forced) const;

  InputTimelineParams params_;
  std::array<Ring, kInputKindCount> rings_;
  bool started_ = false;        ///< a grid exists
  double t0_s_ = 0.0;           ///< its first point [s]
  double step_s_ = 0.0;         ///< its spacing [s]
  std::uint64_t next_k_ = 0;    ///< index of the next step
  double newest_s_ = 0.0;       ///< newest stamp pushed since the grid started [s]
  std::uint64_t steps_past_lagging_ = 0, full_rings_ = 0;
};

}  // namespace tread_wear
