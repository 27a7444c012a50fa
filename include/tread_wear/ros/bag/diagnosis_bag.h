#pragma once
/// @file diagnosis_bag.h
/// ROS-side adapter of the mismatch diagnosis: a rosbag of drives or rig programs -> run records (run_table.h),
/// one per wheel and segment between consecutive measurement checkpoints of that wheel. Topics, for every wheel
/// <w> that has checkpoints:
///   wheels/<w>/load                tread_wear/WheelLoad         node input
///   wheels/<w>/slip                tread_wear/WheelSlip         node input
///   wheels/<w>/speed               tread_wear/WheelSpeed        node input
///   wheels/<w>/tread_temperature   tread_wear/TreadTemperature  node input (optional) = measured tread temperature
///   wheels/<w>/measured/mass       std_msgs/Float64             tire mass checkpoint [kg] (weighing), or
///   wheels/<w>/measured/tread_depth std_msgs/Float64            tread depth checkpoint [m] (gauge); the loss between
///                                                               two is depth difference x MaterialParams::
///                                                               massPerDepth_kg_per_m of the tire file. A wheel
///                                                               with both uses the masses. >= 2 per wheel.
///   wheels/<w>/measured/side_force geometry_msgs/WrenchStamped  measured force on the tire, ISO axes (force.y = Fy)
///                                                               [N] (optional)
///   wheels/<w>/measured/cycle      std_msgs/Int32               surface cycle id from then on (optional; a message
///                                                               stamped at a checkpoint belongs to the next segment)
///   measured/covariate             std_msgs/String              a recorded covariate of every wheel from then on,
///                                                               "name=value" (optional; e.g. test=Rural,
///                                                               brand=Michelin): a text covariate `name` per segment,
///                                                               the value in effect before the segment's end (as the
///                                                               cycle), "unknown" before the first
/// Each wheel's inputs go through DriveSegmenter (estimation/drive_segments.h): the replay's grid, staleness and
/// integration rules, so a segment's prediction is the model integrated over its time series, not the model at
/// its means. Per segment: the operating points with their weights, integrated time and distance, the means of
/// speed, load, |alpha|, |kappa|, |1/R| and tread temperature, the load's standard deviation, the mean of the
/// side-force samples, wear rate = loss / integrated distance, cycle id, run order (the segment's index), and the
/// covariates distance_m, duration_s, mass_loss_kg and the text covariate `wheel`.
/// Inputs older than the estimator's stale_timeout_s are not integrated (as in the node): a bag written with
/// sparse messages needs a longer timeout (tread_wear_diagnose --input-timeout-s).
/// Errors: a segment without integrated motion, a mass gain (or depth increase), checkpoints of a wheel not in
/// increasing time, missing input topics.

#include <string>

#include "tread_wear/estimation/drive_replay.h"
#include "tread_wear/io/run_table.h"
#include "tread_wear/model/tire_params.h"

namespace tread_wear {
namespace diagnosis {

/// tire: the tire file (tread depth -> mass), validated; replay: the grid rate, staleness and time-jump rules and
/// the low-speed convention (the replay's). The segments' cells have the default resolution (point_cells.h).
/// @throw std::runtime_error naming the bag and the problem (unreadable, no checkpoints, missing inputs, ...).
RunTable readDiagnosisBag(const std::string& bag_path, const TireParams& tire, const ReplaySettings& replay);

}  // namespace diagnosis
}  // namespace tread_wear
