// tread_wear_calibrate: bounded least-squares calibration to a run table (usage: --help; logic in calibrate_cli.h).
#include <iostream>

#include "tread_wear/cli/calibrate_cli.h"

int main(int argc, char** argv) { return tread_wear::runCalibrateCli(argc, argv, std::cout, std::cerr); }
