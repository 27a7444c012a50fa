// tread_wear_reference_models: the paper's Table 5 reproduced (usage: --help; logic in reference_models_cli.h).
#include <iostream>

#include "tread_wear/cli/reference_models_cli.h"

int main(int argc, char** argv) { return tread_wear::runReferenceModelsCli(argc, argv, std::cout, std::cerr); }
