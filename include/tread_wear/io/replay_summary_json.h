#pragma once
/// @file replay_summary_json.h
/// The summary of a drive replay (estimation/drive_replay.h) as JSON, the file tread_wear_replay --summary writes.

#include <nlohmann/json.hpp>

#include "tread_wear/estimation/drive_replay.h"

namespace tread_wear {

/// The summary as JSON (docs/drive.md, "Summary JSON").
nlohmann::json replaySummaryToJson(const ReplaySummary& summary, const ReplaySettings& settings);

}  // namespace tread_wear
