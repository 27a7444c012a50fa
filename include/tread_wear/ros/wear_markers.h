#pragma once
/// @file wear_markers.h
/// rviz markers of one wheel's contact patch, drawn in the wheel's contact frame (ISO 8855 tire axes):
///   ns "<wheel>/wear"   the patch as cells coloured by the local wear rate w_r [kg/(m m^2)] on a log scale
///                       (dark blue = lowest in the patch, yellow = highest);
///   ns "<wheel>/zones"  the same cells beside it (offset to +y by 2.5 b) coloured by contact state:
///                       green = exact stick, yellow = creep (0 < |v_s| <= v_m), red = slide (|v_s| > v_m);
///   ns "<wheel>/label"  two lines ahead of both patches: wheel and status; accumulated loss [mg], distance [km],
///                       slide fraction. Text height a quarter of the patch size, at least 1 cm.
/// Not real-time code: called at the marker rate from a non-RT timer.

#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/brush_wear_model.h"

namespace tread_wear {

/// Appends the wheel's three markers to *array (ids 0, 1, 2 in the wheel's namespaces).
/// @param fields local fields of the last evaluation; when fields.n_x_nodes == 0 only the label is drawn.
void appendWheelMarkers(const std::string& wheel, const std::string& frame_id, const ros::Time& stamp,
                        const PatchFields& fields, const WearResult& result, const WheelOutput& output,
                        visualization_msgs::MarkerArray* array);

}  // namespace tread_wear
