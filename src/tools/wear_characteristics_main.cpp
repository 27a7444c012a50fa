// tread_wear_wear_characteristics: the paper's Section 4.3 sweeps as CSV (usage: --help; logic in
// wear_characteristics_cli.h).
#include <iostream>

#include "tread_wear/cli/wear_characteristics_cli.h"

int main(int argc, char** argv) { return tread_wear::runWearCharacteristicsCli(argc, argv, std::cout, std::cerr); }
