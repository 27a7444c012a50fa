#pragma once
/// @file replay_summary_json.h
/// The summary of a drive replay (estimation/drive_replay.h) as JSON, the file tread_wear_replay --summary writes.
/// The functions return the file's text, so that the bag tools never touch the JSON library.

#include <string>

#include "tread_wear/estimation/drive_replay.h"

namespace tread_wear {

/// What the replay tool knows beside the summary: its input and what reading and computing cost.
struct ReplayRun {
  std::string input;           ///< the input bag, as given
  double bag_read_s = 0.0;     ///< wall time of reading the bag [s]
  double compute_cpu_s = 0.0;  ///< CPU time of all replay threads: a load-independent cost measure [s]
  std::string drive_info;      ///< the bag's drive metadata (io/drive_info_json.h), valid JSON; empty: none
};

/// The summary file's text (docs/drive.md, "Summary JSON"): the replay's settings, per-wheel and per-phase
/// results, input, bag_read_s, compute_cpu_s and, when the bag has drive metadata, that document under "drive".
std::string replaySummaryDocument(const ReplaySummary& summary, const ReplaySettings& settings, const ReplayRun& run);

/// The summary file's text of a replay that failed or has not finished (yet): complete false, the reason and
/// the input, so that no earlier summary at the same path looks complete.
std::string incompleteReplaySummary(const std::string& input, const std::string& reason);

}  // namespace tread_wear
