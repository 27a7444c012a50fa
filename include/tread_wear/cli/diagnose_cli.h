#pragma once
/// @file diagnose_cli.h
/// The tread_wear_diagnose tool as a function over streams, so that the main stays a few lines and tests can run it
/// in-process. Exit codes: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <functional>
#include <ostream>
#include <string>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/io/run_table.h"

namespace tread_wear {
namespace diagnosis {

/// Converts a rosbag into run records (the ROS-side adapter: ros/bag/diagnosis_bag.h), with the tire file (tread
/// depth to mass) and the replay's rules for integrating each wheel's inputs.
/// @throw std::exception with a message naming the problem.
using BagReader =
    std::function<RunTable(const std::string& bag_path, const TireParams& tire, const ReplaySettings& replay)>;

/// tread_wear_diagnose --params FILE (--runs FILE.csv | --bag FILE.bag) --report DIR
///     [--orientation literal|flipped] [--preset auto|fast|standard|fine|reference]
///     [--force-noise-model auto|additive|relative|combined] [--wear-noise-model auto|additive|relative|combined]
///     [--candidates a,b,...] [--max-terms N] [--alpha-locate X] [--alpha-select X] [--detection-power X] [--seed N]
///     [--plot-script PATH | --no-plots] [--input-timeout-s S] [--update-rate-hz HZ]
/// A bag's inputs are integrated on the replay's grid (--update-rate-hz, default 100) and an input older than
/// --input-timeout-s (default 0.5, the node's) is not integrated: a bag written with sparse messages (a rig
/// program with one sample per minute) needs a longer timeout.
/// Writes DIR/diagnosis.json, DIR/report.md, DIR/residuals.csv and (with the plot script) DIR/*.png. The preset
/// decision (diagnosis.h, step 0) goes to `err`, with a warning when a given preset fails its solver-error check; a
/// refusal (even `fine` too coarse for the noise) is bad data, exit 1.
/// `bag_reader` may be empty (built without rosbag): --bag is then a usage error. `default_plot_script` is used
/// unless --plot-script or --no-plots is given; an empty or missing script skips the plots with a note.
int runDiagnoseCli(int argc, const char* const argv[], const BagReader& bag_reader,
                   const std::string& default_plot_script, std::ostream& out, std::ostream& err);

}  // namespace diagnosis
}  // namespace tread_wear
