// tread_wear_convergence: convergence study of the reference solver and the marcher (docs/convergence.md).
#include <iostream>

#include "tread_wear/cli/convergence_cli.h"

int main(int argc, char** argv) { return tread_wear::runConvergenceCli(argc, argv, std::cout, std::cerr); }
