// tread_wear_conceal: recordings with a hidden library effect and its answer (docs/diagnosis.md).
#include <iostream>

#include "tread_wear/cli/conceal_cli.h"
#include "tread_wear/ros/bag/diagnosis_bag.h"

int main(int argc, char** argv) {
  return tread_wear::diagnosis::runConcealCli(argc, argv, tread_wear::diagnosis::readDiagnosisBag, std::cout,
                                              std::cerr);
}
