#pragma once
/// @file reference_models_cli.h
/// The tread_wear_reference_models tool as a function over streams, so that the main stays one line and tests
/// can run it in-process. Exit codes: 0 success, 1 bad data (parameter file, run table, output directory), 2 bad usage.

#include <ostream>

namespace tread_wear {

/// tread_wear_reference_models --params FILE --runs RUNS.csv [--orientation literal|flipped] [--grid NX,NY]
///     [--out-dir DIR]
/// Table 5: fits Opt (w1..w4 of the brush model), M_P and M_EP (Eq 26; M_PT, M_EPT only when every run has a
/// tread temperature), each with leave-one-condition-out RMSER, beside the paper's values and the paper's
/// parameters evaluated on the same runs. Writes table5.md and table5.json into DIR (default docs/figures).
int runReferenceModelsCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace tread_wear
