// tread_wear_replay: runs a recorded drive through the node's estimator offline (no ROS master), writes the wear
// topics to a bag, a per-wheel summary JSON and a time series for plots. Usage and formats: docs/drive.md; logic in
// ros/bag/replay_cli.h.
#include <unistd.h>

#include <iostream>

#include "tread_wear/ros/bag/replay_cli.h"

int main(int argc, char** argv) {
  return tread_wear::runReplayCli(argc, argv, TREAD_WEAR_SHARE_DIR, std::cout, std::cerr, isatty(STDERR_FILENO) != 0);
}
