// tread_wear_node: live per-wheel tread wear estimation (docs/node.md).
#include <ros/ros.h>

#include <cstring>
#include <iostream>

#include "tread_wear/ros/node_help.h"
#include "tread_wear/ros/tread_wear_node.h"

int main(int argc, char** argv) {
  // Before ros::init: help needs no master and no parameters.
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::cout << tread_wear::nodeHelp();
      return 0;
    }
  ros::init(argc, argv, "tread_wear_node");
  ros::AsyncSpinner spinner(2);  // inputs and services must not wait for each other
  tread_wear::TreadWearNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  if (!node.initialize()) return 1;
  spinner.start();
  ros::waitForShutdown();
  node.shutdown();
  return 0;
}
