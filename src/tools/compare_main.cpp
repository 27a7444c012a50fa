// tread_wear_compare: the model against measured runs, RMSER per orientation (usage: --help; logic in cli_tools.h).
#include <iostream>

#include "tread_wear/cli/cli_tools.h"

int main(int argc, char** argv) { return tread_wear::runCompareCli(argc, argv, std::cout, std::cerr); }
