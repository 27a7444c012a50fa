// tread_wear_eval: the brush wear model on a CSV of operating conditions (usage: --help; logic in eval_cli.h).
#include <iostream>

#include "tread_wear/cli/eval_cli.h"

int main(int argc, char** argv) { return tread_wear::runEvalCli(argc, argv, std::cin, std::cout, std::cerr); }
