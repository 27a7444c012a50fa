#pragma once
/// @file cli.h
/// The diagnosis command-line tools as functions, so that the mains stay a few lines and tests can run them
/// in-process. Exit codes as cli_tools.h: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <functional>
#include <ostream>
#include <string>

#include "tread_wear/io/run_table.h"

namespace tread_wear {
namespace diagnosis {

/// Converts a rosbag into run records (the ROS-side adapter; see src/tools/ros/diagnosis_bag.h).
/// @throw std::exception with a message naming the problem.
using BagReader = std::function<RunTable(const std::string& bag_path)>;

/// tread_wear_diagnose --params FILE (--runs FILE.csv | --bag FILE.bag) --report DIR
///     [--orientation literal|flipped] [--preset fast|standard] [--candidates a,b,...] [--max-terms N]
///     [--alpha-locate X] [--alpha-select X] [--seed N] [--plot-script PATH | --no-plots]
/// Writes DIR/diagnosis.json, DIR/report.md, DIR/residuals.csv and (with the plot script) DIR/*.png.
/// `bag_reader` may be empty (built without rosbag): --bag is then a usage error. `default_plot_script` is used
/// unless --plot-script or --no-plots is given; an empty or missing script skips the plots with a note.
int runDiagnoseCli(int argc, const char* const argv[], const BagReader& bag_reader,
                   const std::string& default_plot_script, std::ostream& out, std::ostream& err);

/// tread_wear_conceal --params FILE --effect NAME|none --runs OUT.csv --answer OUT.json [--magnitude X]
///     [--design table2|small] [--wear-noise RSD] [--force-noise N] [--seed N] [--orientation literal|flipped]
///     [--information]   (also the case's detectability reference, detectability.h, on stdout and in the answer)
/// tread_wear_conceal --list   prints the library (name, parameters, default magnitude, statement).
int runConcealCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

/// tread_wear_diagnosis_harness --params FILE [--quick] [--design table2|small] [--repeats N] [--controls N]
///     [--effects a,b] [--noise 0.05,0.10] [--one-magnitude] [--information] [--alpha-select X] [--jobs N]
///     [--seed N] [--csv OUT.csv]
/// Prints progress to err and the success-rate table to out; --information adds each case's detectability
/// reference (detectability.h).
int runHarnessCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace diagnosis
}  // namespace tread_wear
