#pragma once
/// @file node_diagnostics.h
/// The node's diagnostics (/diagnostics, docs/node.md): one status per wheel, one for the update loop (with the
/// last rejected reconfiguration) and one for persistence, and the throttled warnings that go with them. The loop
/// only counts; this part, on the diagnostics timer, turns counts into rates, levels and log lines. No node
/// handle: the tests call the diagnose functions directly.

#include <diagnostic_updater/diagnostic_updater.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "tread_wear/ros/loop_status.h"
#include "tread_wear/ros/node_persistence.h"
#include "tread_wear/ros/node_reconfigure.h"
#include "tread_wear/ros/wheel_pipeline.h"

namespace tread_wear {

class NodeDiagnostics {
 public:
  /// Everything passed must outlive this object.
  NodeDiagnostics(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, const LoopStatus& loop,
                  const NodePersistence& persistence, const NodeReconfigure& reconfigure);

  /// Registers "update loop", "persistence" and "wheel <name>" with the updater (ages against ros::Time::now()).
  void addTo(diagnostic_updater::Updater* updater);

  /// Wheel `index` at node time now_s [s] (input ages) and steady time wall_s [s] (input rates since the last call).
  void diagnoseWheel(std::size_t index, double now_s, double wall_s, diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnoseLoop(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnosePersistence(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  /// What the previous report of a wheel saw, to tell new events from old ones.
  struct WheelHistory {
    std::array<std::uint64_t, kInputKindCount> received{};
    std::uint64_t rejected = 0, backward = 0, forward = 0;
    double wall_s = 0.0;
  };

  const std::vector<std::unique_ptr<WheelPipeline>>& wheels_;
  const LoopStatus& loop_;
  const NodePersistence& persistence_;
  const NodeReconfigure& reconfigure_;
  std::vector<WheelHistory> history_;
  std::uint64_t last_cycle_overruns_ = 0;
};

}  // namespace tread_wear
