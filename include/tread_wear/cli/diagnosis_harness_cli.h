#pragma once
/// @file diagnosis_harness_cli.h
/// The tread_wear_diagnosis_harness tool as a function over streams, so that the main stays a few lines and tests can
/// run it in-process. Exit codes: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <ostream>

namespace tread_wear {
namespace diagnosis {

/// tread_wear_diagnosis_harness --params FILE [--quick] [--design table2|small|low_slip] [--repeats N] [--controls N]
///     [--effects a,b] [--noise 0.05,0.10] [--one-magnitude] [--information] [--alpha-select X] [--jobs N]
///     [--seed N] [--csv OUT.csv] [--preset auto|NAME] [--generator-preset NAME (default reference)]
///     [--force-noise-model auto|additive|relative|combined] [--wear-noise-model auto|additive|relative|combined]
/// Prints progress to err and the success-rate table to out; --information adds each case's detectability
/// reference (proving/detectability.h).
int runHarnessCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace diagnosis
}  // namespace tread_wear
