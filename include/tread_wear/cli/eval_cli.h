#pragma once
/// @file eval_cli.h
/// The tread_wear_eval tool as a function over streams, so that the main stays one line and tests can run it
/// in-process. Exit codes: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <istream>
#include <ostream>

namespace tread_wear {

/// tread_wear_eval --params FILE [--orientation literal|flipped] [--preset NAME | --grid NXxNS] CONDITIONS.csv|-
/// Evaluates every row of a conditions CSV (conditions_csv.h) and writes the CSV to out. Nothing is written to
/// out unless every row evaluated; errors go to err.
int runEvalCli(int argc, const char* const argv[], std::istream& in, std::ostream& out, std::ostream& err);

}  // namespace tread_wear
