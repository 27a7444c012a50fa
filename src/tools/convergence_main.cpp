// tread_wear_convergence: convergence study of the reference solver and the marcher (docs/convergence.md).
#include <iostream>

#include "tread_wear/core/convergence_study.h"

int main(int argc, char** argv) { return tread_wear::runConvergenceCli(argc, argv, std::cout, std::cerr); }
