#pragma once
/// @file node_services.h
/// The node's two services as functions of the wheels, without a node handle (tested without a master):
///   evaluate_wear  planner: hypothetical states of one wheel through the live inputs' validation (WheelInputs with
///                  the node's limits: one rule per input, the one of the live topics), then the live evaluation
///                  (evaluateInputs: the same operating point and zero-load rule), on the wheel's planner model;
///   reset_wheel    tire change: zero the wheel's accumulators, record the new tire id.

#include <memory>
#include <string>
#include <vector>

#include "tread_wear/EvaluateWear.h"
#include "tread_wear/ResetWheel.h"
#include "tread_wear/ros/wheel_pipeline.h"

namespace tread_wear {

/// evaluate_wear for `wheels`; configured = the preset used when the request names none. A rejected state's error
/// reads "<field> = <value>: must be <constraint>", the constraint with the configured limit's key and value.
void evaluateWear(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, Preset configured,
                  const tread_wear::EvaluateWear::Request& request, tread_wear::EvaluateWear::Response* response);

/// reset_wheel at wall time unix_s [s since 1970]; true when a tire was changed (the caller logs and saves).
bool resetWheel(const std::vector<std::unique_ptr<WheelPipeline>>& wheels, double unix_s,
                const tread_wear::ResetWheel::Request& request, tread_wear::ResetWheel::Response* response);

}  // namespace tread_wear
