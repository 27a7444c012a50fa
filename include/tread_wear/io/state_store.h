#pragma once
/// @file state_store.h
/// Persistence of the accumulated tread loss per wheel and tire: the product's memory across restarts.
///
/// File: JSON, `{"format": "tread_wear_state", "version": 1, "saved_unix_s": ..., "wheels": [{"name",
/// "tire_id", "accumulated_loss_kg", "distance_m", "reset_unix_s"}]}`.
/// Saving is atomic: the content goes to `<path>.tmp`, is fsync'ed, renamed over `<path>` and the directory
/// is fsync'ed, so a crash at any point leaves either the old or the new complete file.
/// Loading never silently zeroes: a missing file is an empty state (first start); a file that cannot be
/// parsed, has another format or version, or holds non-finite or negative values is reported with the
/// reason and moved aside to `<path>.corrupt-<UTC timestamp>` (or `.incompatible-...`), so the data can
/// still be recovered by hand, and the caller decides what to do.
/// Not for the real-time loop: it allocates and does blocking I/O.

#include <string>
#include <vector>

namespace tread_wear {

/// Saved state of one wheel.
struct WheelRecord {
  std::string name;                  ///< wheel name (node configuration)
  std::string tire_id;               ///< identifier of the mounted tire
  double accumulated_loss_kg = 0.0;  ///< accumulated tread mass loss [kg], >= 0
  double distance_m = 0.0;           ///< distance travelled while estimating [m], >= 0
  double reset_unix_s = 0.0;         ///< wall time of the last tire change [s since 1970], 0 = unknown
};

struct StateFile {
  double saved_unix_s = 0.0;  ///< wall time of the save [s since 1970]
  std::vector<WheelRecord> wheels;

  /// Record of a wheel by name, or nullptr.
  const WheelRecord* find(const std::string& name) const;
  WheelRecord* find(const std::string& name);
};

enum class LoadStatus {
  kLoaded = 0,        ///< file read and valid
  kMissing = 1,       ///< no file: empty state (first start)
  kCorrupt = 2,       ///< unreadable, not JSON, or invalid values: moved aside
  kIncompatible = 3,  ///< another format or version: moved aside
  kIoError = 4        ///< exists but cannot be read, is no regular file (a directory), or could not be moved aside:
                      ///< left in place
};
const char* loadStatusName(LoadStatus status);

struct LoadResult {
  LoadStatus status = LoadStatus::kMissing;
  StateFile state;         ///< the loaded state (empty unless kLoaded)
  std::string message;     ///< what was wrong, for the log
  std::string moved_to;    ///< where a bad file was moved, if it was
};

class StateStore {
 public:
  static constexpr int kVersion = 1;
  static constexpr const char* kFormat = "tread_wear_state";

  /// @param path state file path; its directory must exist.
  explicit StateStore(std::string path) : path_(std::move(path)) {}

  /// Loads the file; see the file comment for the handling of bad files.
  LoadResult load() const;
  /// Writes atomically; false with *error naming the failed step (open, write, fsync, rename).
  bool save(const StateFile& state, std::string* error) const;
  const std::string& path() const { return path_; }

  /// Serialises and parses without touching the disk (also used by the tests).
  static std::string toJson(const StateFile& state);
  /// false with *error saying what is wrong; *incompatible tells a format/version mismatch from corruption.
  static bool fromJson(const std::string& text, StateFile* state, std::string* error, bool* incompatible);

 private:
  std::string path_;
};

}  // namespace tread_wear
