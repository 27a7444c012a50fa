// tread_wear_drive: generates a test drive (speed profile + route + vehicle model) as a bag of the node's inputs.
// Usage and model: docs/drive.md; logic in ros/bag/drive_cli.h.
#include <iostream>

#include "tread_wear/ros/bag/drive_cli.h"

int main(int argc, char** argv) {
  return tread_wear::runDriveCli(argc, argv, TREAD_WEAR_SHARE_DIR, std::cout, std::cerr);
}
