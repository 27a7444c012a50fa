// tread_wear_diagnosis_harness: success rates of the diagnosis on generated cases (docs/diagnosis.md).
#include <iostream>

#include "tread_wear/cli/diagnosis_harness_cli.h"

int main(int argc, char** argv) { return tread_wear::diagnosis::runHarnessCli(argc, argv, std::cout, std::cerr); }
