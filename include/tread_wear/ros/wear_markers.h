#pragma once
/// @file wear_markers.h
/// rviz markers of each wheel's contact patch, drawn in the wheel's contact frame (ISO 8855 tire axes):
///   ns "<wheel>/wear"   the patch as cells coloured by the local wear rate w_r [kg/(m m^2)] on a log scale
///                       (dark blue = lowest in the patch, yellow = highest);
///   ns "<wheel>/zones"  the same cells beside it (offset to +y by 2.5 b) coloured by contact state:
///                       green = exact stick, yellow = creep (0 < |v_s| <= v_m), red = slide (|v_s| > v_m);
///   ns "<wheel>/label"  ahead of both patches: wheel and status; accumulated loss [mg], distance [km], slide
///                       fraction; with the step's inputs also load [kN], slip angle [deg], slip ratio [-] and the
///                       wear rate [mg/km] (why the wheel wears). Text height a quarter of the patch size, >= 1 cm.
/// Not real-time code: called at the marker rate from a non-RT timer.

#include <visualization_msgs/MarkerArray.h>

#include <memory>
#include <string>
#include <vector>

#include "tread_wear/estimation/wheel_estimator.h"
#include "tread_wear/model/brush_wear_model.h"
#include "tread_wear/ros/wheel_pipeline.h"

namespace tread_wear {

/// Appends the wheel's three markers to *array (ids 0, 1, 2 in the wheel's namespaces).
/// @param fields local fields of the last evaluation; when fields.n_x_nodes == 0 only the label is drawn.
/// @param inputs the step's inputs (load, slips) for the label's second part; nullptr: two lines only.
void appendWheelMarkers(const std::string& wheel, const std::string& frame_id, const ros::Time& stamp,
                        const PatchFields& fields, const WearResult& result, const WheelOutput& output,
                        visualization_msgs::MarkerArray* array, const WheelInputs* inputs = nullptr);

/// The markers of every wheel's last loop step. The loop computes no local fields (they cost time the loop does
/// not have), so each wheel's patch is evaluated again here, on a model of its own, at the operating point of that
/// step (operatingPoint(): the loop's point, tread temperature included) and the preset the step used.
class WearMarkers {
 public:
  /// The wheels must outlive this object.
  explicit WearMarkers(const std::vector<std::unique_ptr<WheelPipeline>>& wheels);
  /// Appends the markers of every wheel, stamped `stamp`, to *array.
  void build(const ros::Time& stamp, visualization_msgs::MarkerArray* array);

 private:
  struct Wheel {
    const WheelPipeline* pipeline;
    std::unique_ptr<WearModel> model;
    PatchFields fields;
  };
  std::vector<Wheel> wheels_;
};

}  // namespace tread_wear
