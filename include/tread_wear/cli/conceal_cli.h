#pragma once
/// @file conceal_cli.h
/// The tread_wear_conceal tool as a function over streams, so that the main stays a few lines and tests can run it
/// in-process. Exit codes: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <ostream>

namespace tread_wear {
namespace diagnosis {

/// tread_wear_conceal --params FILE --effect NAME|none --runs OUT.csv --answer OUT.json [--magnitude X]
///     [--design table2|small|low_slip] [--wear-noise RSD] [--force-noise N] [--seed N]
///     [--orientation literal|flipped]
///     [--generator-preset NAME]   (the preset that generates the truth; default reference, the converged grid)
///     [--information [--preset NAME]]   (also the case's detectability reference, proving/detectability.h, on
///                                        stdout and in the answer, for a diagnosis at --preset, default fast)
/// tread_wear_conceal --list   prints the library (name, parameters, default magnitude, statement).
int runConcealCli(int argc, const char* const argv[], std::ostream& out, std::ostream& err);

}  // namespace diagnosis
}  // namespace tread_wear
