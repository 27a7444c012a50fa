#pragma once
/// @file node_persistence.h
/// The node's memory across restarts (io/state_store.h): restore the wheels at start-up, save them periodically,
/// on a tire change and at shutdown, and keep what went wrong for diagnostics. A file that cannot be read (an I/O
/// error, a directory at the path) disables saving, so that a good file is never overwritten with zeros; a corrupt
/// or incompatible one has been moved aside by the store and the wheels start from zero. Free of any middleware: it
/// reports through the LogSink its front end gives (tread_wear_node: rosconsole). Not for the loop: it logs and does
/// blocking I/O.

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "tread_wear/io/state_store.h"
#include "tread_wear/pipeline/wheel_pipeline.h"

namespace tread_wear {

enum class LogLevel { kDebug, kInfo, kWarn, kError };
/// Where a front end's log lines go (called from the thread that restores or saves).
using LogSink = std::function<void(LogLevel level, const std::string& text)>;

class NodePersistence {
 public:
  /// state_file "" = persistence off. A failed save is logged at most every 30 s; no sink: not logged.
  explicit NodePersistence(const std::string& state_file, LogSink log = LogSink());

  /// Loads the file and restores the wheels it has (their saved tire ids replace the configured ones).
  void restore(const std::vector<std::unique_ptr<WheelPipeline>>& wheels);
  /// Saves every wheel, keeping the file's records of wheels not configured now; `reason` goes to the log.
  void save(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, const char* reason);

  struct Status {
    bool saving = false;               ///< saves go to the file
    std::string state_file;            ///< "" = persistence off
    std::string restore;               ///< what start-up found: loadStatusName()
    std::string problem;               ///< "" = fine
    double seconds_since_save = -1.0;  ///< wall time since the last good save [s], -1 = none yet
  };
  Status status() const;

 private:
  std::string state_file_;
  mutable std::mutex mutex_;
  std::unique_ptr<StateStore> store_;  ///< guarded by mutex_; null = saving off
  StateFile saved_;                    ///< guarded by mutex_: last file content (keeps unconfigured wheels)
  std::string restore_report_;         ///< guarded by mutex_
  std::string problem_;                ///< guarded by mutex_
  double last_save_unix_s_ = 0.0;      ///< guarded by mutex_
  double last_failure_log_unix_s_ = -1e300;  ///< guarded by mutex_
  LogSink log_;
};

}  // namespace tread_wear
