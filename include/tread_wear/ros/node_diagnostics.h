#pragma once
/// @file node_diagnostics.h
/// The node's diagnostics (/diagnostics, docs/node.md): one status per wheel, one for the vehicle, one for the
/// update loop (with the last rejected reconfiguration) and one for persistence, and the throttled warnings that go
/// with them. The loop only counts; this part, on the diagnostics timer, turns counts into rates, levels and log
/// lines. A wheel's and the vehicle's level cover everything since their previous report, not only the instant of
/// the report: time a wheel left unintegrated in between (stale, invalid, no input, time jump) is WARN with its
/// seconds, ERROR above kErrorUnintegratedShare. No node handle: the tests call the diagnose functions directly.

#include <diagnostic_updater/diagnostic_updater.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "tread_wear/ros/loop_status.h"
#include "tread_wear/pipeline/node_persistence.h"
#include "tread_wear/ros/node_reconfigure.h"
#include "tread_wear/ros/wheel_pipeline.h"

namespace tread_wear {

/// Share of the elapsed time since the previous report that a wheel left unintegrated for stale or invalid input
/// or a time jump above which its report, and the vehicle's, is ERROR [-] (docs/node.md). Time before a wheel's
/// first input (no_input) is WARN whatever its share: the node is waiting, not failing.
constexpr double kErrorUnintegratedShare = 0.5;

class NodeDiagnostics {
 public:
  /// Everything passed must outlive this object.
  NodeDiagnostics(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, const LoopStatus& loop,
                  const NodePersistence& persistence, const NodeReconfigure& reconfigure);

  /// Registers "update loop", "persistence", "wheel <name>" and "vehicle" with the updater (ages against
  /// ros::Time::now()).
  void addTo(diagnostic_updater::Updater* updater);

  /// Wheel `index` at node time now_s [s] (input ages) and steady time wall_s [s] (input rates since the last call).
  void diagnoseWheel(std::size_t index, double now_s, double wall_s, diagnostic_updater::DiagnosticStatusWrapper& stat);
  /// The vehicle: total loss, and whether every wheel integrated all the time since the previous vehicle report.
  void diagnoseVehicle(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnoseLoop(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnosePersistence(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  /// A wheel's integrated and unintegrated time counters at a report, to take the interval's from the next.
  struct TimeCounters {
    double integrated_s = 0.0;
    std::array<double, kWheelStatusCount> unintegrated_by_cause_s{};
  };
  /// A wheel's time between two reports [s]: integrated, and unintegrated by WheelStatus cause.
  struct IntervalTime {
    double integrated_s = 0.0, unintegrated_s = 0.0;
    double fault_s = 0.0;  ///< unintegrated for stale or invalid input or a time jump (not for no input)
    std::array<double, kWheelStatusCount> by_cause_s{};
    double faultShare() const;     ///< fault_s over the interval's elapsed time [-]
    std::string describe() const;  ///< e.g. "0.520 s of 1.000 s not integrated (stale_input 0.520 s)"
  };
  /// The interval from *previous to s; *previous becomes s's counters.
  static IntervalTime takeInterval(const WheelSnapshot& s, TimeCounters* previous);

  /// What the previous report of a wheel saw, to tell new events from old ones.
  struct WheelHistory {
    std::array<std::uint64_t, kInputKindCount> received{};
    std::uint64_t rejected = 0, backward = 0, forward = 0;
    double wall_s = 0.0;
    TimeCounters time;
  };

  const std::vector<std::unique_ptr<WheelPipeline>>& wheels_;
  const LoopStatus& loop_;
  const NodePersistence& persistence_;
  const NodeReconfigure& reconfigure_;
  std::vector<WheelHistory> history_;
  std::vector<TimeCounters> vehicle_history_;  ///< each wheel's counters at the previous vehicle report
  std::uint64_t last_cycle_overruns_ = 0;
};

}  // namespace tread_wear
