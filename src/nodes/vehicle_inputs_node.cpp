// vehicle_inputs_node: per-wheel inputs of the wear node from the car's own sensors (docs/vehicle_inputs_node.md).
#include <ros/ros.h>

#include "tread_wear/ros/vehicle_inputs_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "vehicle_inputs_node");
  tread_wear::VehicleInputsNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  if (!node.initialize()) return 1;
  ros::spin();  // one thread: the callbacks and the publish cycle never run at the same time
  node.shutdown();
  return 0;
}
