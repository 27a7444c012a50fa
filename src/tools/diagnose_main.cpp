// tread_wear_diagnose: mismatch diagnosis of recordings (run table or rosbag) against the model (docs/diagnosis.md).
#include <iostream>

#include "tread_wear/core/diagnosis/cli.h"
#ifdef TREAD_WEAR_DIAGNOSIS_ROSBAG
#include "diagnosis_bag.h"
#endif
#ifndef TREAD_WEAR_PLOT_SCRIPT
#define TREAD_WEAR_PLOT_SCRIPT ""
#endif

int main(int argc, char** argv) {
  tread_wear::diagnosis::BagReader bag_reader;
#ifdef TREAD_WEAR_DIAGNOSIS_ROSBAG
  bag_reader = tread_wear::diagnosis::readDiagnosisBag;
#endif
  return tread_wear::diagnosis::runDiagnoseCli(argc, argv, bag_reader, TREAD_WEAR_PLOT_SCRIPT, std::cout, std::cerr);
}
