// tread_wear_diagnose: mismatch diagnosis of recordings (run table or rosbag) against the model (docs/diagnosis.md).
#include <iostream>

#include "tread_wear/cli/diagnose_cli.h"
#include "tread_wear/ros/bag/diagnosis_bag.h"

int main(int argc, char** argv) {
  return tread_wear::diagnosis::runDiagnoseCli(argc, argv, tread_wear::diagnosis::readDiagnosisBag,
                                               TREAD_WEAR_PLOT_SCRIPT, std::cout, std::cerr);
}
