#pragma once
/// @file conceal_cli.h
/// The tread_wear_conceal tool as a function over streams, so that the main stays a few lines and tests can run it
/// in-process. Exit codes: 0 success, 1 bad data (file, parameter, row), 2 bad usage.

#include <ostream>

#include "tread_wear/cli/diagnose_cli.h"

namespace tread_wear {
namespace diagnosis {

/// tread_wear_conceal --params FILE --effect NAME|none --runs OUT.csv --answer OUT.json [--magnitude X]
///     [--design table2|small|low_slip] [--wear-noise RSD] [--force-noise N] [--seed N]
///     [--orientation literal|flipped]
///     [--generator-preset NAME]   (the preset that generates the truth; default reference, the converged grid)
///     [--information [--preset NAME]]   (also the case's detectability reference, proving/detectability.h, on
///                                        stdout and in the answer, for a diagnosis at --preset, default fast)
/// tread_wear_conceal --params FILE --effect NAME|none --bag DRIVES.bag --segments OUT.csv --answer OUT.json
///     [--magnitude X] [--orientation ...] [--generator-preset NAME] [--input-timeout-s S] [--update-rate-hz HZ]
///     the truth of a bag's drive segments (the diagnosis's bag input, ros/bag/diagnosis_bag.h; its checkpoints only
///     delimit the segments) with the effect hidden (concealInRecordings): per wheel and segment the distance, true
///     wear rate and mass loss in OUT.csv, for a caller that writes the measurements (tread_wear_fleet_generate).
/// tread_wear_conceal --list   prints the library (name, parameters, default magnitude, statement).
/// `bag_reader` may be empty (built without rosbag): --bag is then a usage error.
int runConcealCli(int argc, const char* const argv[], const BagReader& bag_reader, std::ostream& out,
                  std::ostream& err);

}  // namespace diagnosis
}  // namespace tread_wear
