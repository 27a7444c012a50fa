// tread_wear_eval: the brush wear model on a CSV of operating conditions (usage: --help; logic in cli_tools.h).
#include <iostream>

#include "tread_wear/cli/cli_tools.h"

int main(int argc, char** argv) { return tread_wear::runEvalCli(argc, argv, std::cin, std::cout, std::cerr); }
