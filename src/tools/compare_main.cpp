// tread_wear_compare: the model against measured runs, RMSER per orientation (usage: --help; logic in compare_cli.h).
#include <iostream>

#include "tread_wear/cli/compare_cli.h"

int main(int argc, char** argv) { return tread_wear::runCompareCli(argc, argv, std::cout, std::cerr); }
