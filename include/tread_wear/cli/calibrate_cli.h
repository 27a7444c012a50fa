#pragma once
/// @file calibrate_cli.h
/// The tread_wear_calibrate tool as a function over streams, so that the main stays one line and tests
/// can run it in-process. Exit codes: 0 success, 1 bad data (parameter file, run table, failed fit), 2 bad usage.

#include <ostream>

namespace tread_wear {

/// tread_wear_calibrate --params FILE --runs RUNS.csv [--fit NAMES] [--target auto|side_force|wear|both]
///     [--orientation literal|flipped] [--prior-weight W] [--fy-weight W] [--wear-weight W] [--grid NX,NY]
///     [--no-cv] [--robust-se] --json OUT.json [--out-params FILE.yaml]
/// Fits the named parameters (calibration.h), prints the summary, writes the JSON and optionally the
/// calibrated parameter file. Defaults: --fit w1,w2,w3,w4 --target auto --orientation literal
/// --prior-weight 0 --fy-weight 1 --wear-weight 1 --grid 400,24, cross-validation on.
int runCalibrateCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace tread_wear
