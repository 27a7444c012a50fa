#pragma once
/// @file diagnosis_bag.h
/// ROS-side adapter of the mismatch diagnosis: a rosbag of a drive or rig program -> run records (run_table.h),
/// one per segment between consecutive mass checkpoints. Topics (wheel <w>; the first wheel, by name, that has
/// mass checkpoints is used):
///   wheels/<w>/load               tread_wear/WheelLoad         node input
///   wheels/<w>/slip               tread_wear/WheelSlip         node input
///   wheels/<w>/speed              tread_wear/WheelSpeed        node input
///   wheels/<w>/tread_temperature  tread_wear/TreadTemperature  node input (optional) = measured tread temperature
///   wheels/<w>/measured/side_force geometry_msgs/WrenchStamped measured force on the tire, ISO axes (force.y = Fy)
///                                                              [N] (optional)
///   wheels/<w>/measured/mass      std_msgs/Float64             tire mass checkpoint [kg] (weighing; >= 2 needed)
///   wheels/<w>/measured/cycle     std_msgs/Int32               surface cycle id from then on (optional; a message
///                                                              stamped at a checkpoint belongs to the next segment)
/// Per segment: time-weighted means of speed, slip angle, slip ratio, path curvature, load (with its standard
/// deviation, Eq 23) and tread temperature (inputs held between samples), the mean of the side-force samples,
/// distance = integral of speed, wear rate = (mass before - mass after) / distance, cycle id and run order.
/// Limits: the model is evaluated at the segment means, so segments should be quasi-steady (rig programs,
/// constant-condition road sections); a segment without motion or with a mass gain is an error.

#include <string>

#include "tread_wear/io/run_table.h"

namespace tread_wear {
namespace diagnosis {

/// @throw std::runtime_error naming the bag and the problem (unreadable, no mass checkpoints, missing inputs).
RunTable readDiagnosisBag(const std::string& bag_path);

}  // namespace diagnosis
}  // namespace tread_wear
