#pragma once
/// @file cli_tools.h
/// The offline command-line tools as functions over streams, so that the mains stay one line and tests can
/// run them in-process. Exit codes: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <istream>
#include <ostream>

namespace tread_wear {

/// tread_wear_eval --params FILE [--orientation literal|flipped] [--preset NAME] CONDITIONS.csv|-
/// Evaluates every row of a conditions CSV (conditions_csv.h) and writes the CSV to out. Nothing is written to
/// out unless every row evaluated; errors go to err.
int runEvalCli(int argc, const char* const argv[], std::istream& in, std::ostream& out, std::ostream& err);

/// tread_wear_compare --params FILE --runs RUNS.csv [--orientation literal|flipped|both] [--preset NAME]
///                    [--csv OUT.csv]
/// Prints measured vs predicted Fy and W_r per run (paper units N and g/km) and the RMSERs per orientation.
int runCompareCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace tread_wear
