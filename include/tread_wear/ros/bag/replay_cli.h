#pragma once
/// @file replay_cli.h
/// The tread_wear_replay tool as a function over streams, so that the main stays a few lines and tests can run it
/// in-process. It is here and not in cli because it reads and writes bags.

#include <ostream>
#include <string>

namespace tread_wear {

/// Exit status of tread_wear_replay when the replay ran but did not cover the drive (summary "complete": false).
constexpr int kExitIncompleteReplay = 3;

/// tread_wear_replay IN.bag [--out OUT.bag] [--summary FILE.json] [--timeseries FILE.csv] [--preset NAME]
///     [--wheels CONFIG.yaml] [--rate-hz HZ] [--out-rate-hz HZ] [--timeseries-rate-hz HZ] [--threads N]
///     [--max-span-s S] [--quiet]
/// Runs a recorded drive through the node's estimator offline (no ROS master; docs/drive.md): writes the wear
/// topics to OUT.bag, the per-wheel summary JSON and a time series for plots, and prints the per-wheel results to
/// out. Progress (unless --quiet) and errors go to err; `err_is_terminal` redraws one progress bar instead of
/// printing a line per quarter. The default --wheels is `share_dir`/config/vehicle_wheels.yaml.
/// Returns 0, 1 for bad data (bag, configuration, unwritable output), 2 for bad usage or kExitIncompleteReplay.
int runReplayCli(int argc, const char* const argv[], const std::string& share_dir, std::ostream& out, std::ostream& err,
                 bool err_is_terminal);

}  // namespace tread_wear
