#pragma once
/// @file node_reconfigure.h
/// Live reconfiguration (dynamic_reconfigure, cfg/TreadWear.cfg: update_rate_hz, budget_us, preset) under the
/// start-up rules: a request is applied only when the configuration it gives passes NodeConfig::validate(), the
/// check the node ran at start-up. A rejected request changes nothing and is reported (ERROR log, the "update
/// loop" diagnostic, and the kept values in the server's answer), never clamped. No node handle: tested without
/// a master.

#include <mutex>
#include <string>

#include "tread_wear/TreadWearConfig.h"
#include "tread_wear/io/wheel_config.h"
#include "tread_wear/ros/loop_status.h"

namespace tread_wear {

class NodeReconfigure {
 public:
  /// Starts from the node's (validated) configuration and writes its loop settings into *loop.
  NodeReconfigure(const NodeConfig& config, LoopStatus* loop);

  /// The reconfigurable values in force (the server starts from these, not from the .cfg defaults).
  tread_wear::TreadWearConfig current() const;
  /// The dynamic_reconfigure callback: true when the request was applied (to the loop settings); false when it
  /// was rejected, with *request set back to the values in force.
  bool apply(tread_wear::TreadWearConfig* request);
  /// Why the last request was rejected, "" when it was applied.
  std::string lastRejection() const;

 private:
  mutable std::mutex mutex_;
  NodeConfig config_;      ///< guarded by mutex_: the configuration in force
  LoopStatus* loop_;
  std::string rejection_;  ///< guarded by mutex_
};

}  // namespace tread_wear
