#pragma once
/// @file calibration_cli.h
/// The calibration and wear-characteristics tools as functions over streams (mains stay one line, tests can
/// run them in-process). Exit codes: 0 success, 1 bad data (parameter file, run table, failed fit), 2 bad usage.

#include <ostream>

namespace tread_wear {

/// tread_wear_calibrate --params FILE --runs RUNS.csv [--fit NAMES] [--target auto|side_force|wear|both]
///     [--orientation literal|flipped] [--prior-weight W] [--fy-weight W] [--wear-weight W] [--grid NX,NY]
///     [--no-cv] --json OUT.json [--out-params FILE.yaml]
/// Fits the named parameters (calibration.h), prints the summary, writes the JSON and optionally the
/// calibrated parameter file. Defaults: --fit w1,w2,w3,w4 --target auto --orientation literal
/// --prior-weight 0 --fy-weight 1 --wear-weight 1 --grid 400,24, cross-validation on.
int runCalibrateCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

/// tread_wear_wear_characteristics --params FILE [--orientation literal|flipped] [--out-dir DIR]
/// Section 4.3 sweeps (wear_characteristics.h) as CSV files in DIR (default docs/figures).
int runWearCharacteristicsCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

/// tread_wear_reference_models --params FILE --runs RUNS.csv [--orientation literal|flipped] [--grid NX,NY]
///     [--out-dir DIR]
/// Table 5: fits Opt (w1..w4 of the brush model), M_P and M_EP (Eq 26; M_PT, M_EPT only when every run has a
/// tread temperature), each with leave-one-condition-out RMSER, beside the paper's values and the paper's
/// parameters evaluated on the same runs. Writes table5.md and table5.json into DIR (default docs/figures).
int runReferenceModelsCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace tread_wear
