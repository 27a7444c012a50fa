#pragma once
/// @file compare_cli.h
/// The tread_wear_compare tool as a function over streams, so that the main stays one line and tests can run it
/// in-process. Exit codes: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <ostream>

namespace tread_wear {

/// tread_wear_compare --params FILE --runs RUNS.csv [--orientation literal|flipped|both] [--preset NAME]
///                    [--csv OUT.csv]
/// Prints measured vs predicted Fy and W_r per run (paper units N and g/km) and the RMSERs per orientation.
int runCompareCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace tread_wear
