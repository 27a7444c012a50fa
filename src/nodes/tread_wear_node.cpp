// tread_wear_node: live per-wheel tread wear estimation (docs/node.md).
#include <ros/ros.h>

#include "tread_wear/ros/tread_wear_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "tread_wear_node");
  ros::AsyncSpinner spinner(2);  // inputs and services must not wait for each other
  tread_wear::TreadWearNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  if (!node.initialize()) return 1;
  spinner.start();
  ros::waitForShutdown();
  node.shutdown();
  return 0;
}
