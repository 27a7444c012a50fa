#pragma once
/// @file wear_characteristics_cli.h
/// The tread_wear_wear_characteristics tool as a function over streams, so that the main stays one line and tests
/// can run it in-process. Exit codes: 0 success, 1 bad data (parameter file, output directory), 2 bad usage.

#include <ostream>

namespace tread_wear {

/// tread_wear_wear_characteristics --params FILE [--orientation literal|flipped] [--out-dir DIR]
/// Section 4.3 sweeps (wear_characteristics.h) as CSV files in DIR (default docs/figures).
int runWearCharacteristicsCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace tread_wear
