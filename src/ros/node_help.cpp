#include "tread_wear/ros/node_help.h"

#include "tread_wear/io/wheel_config.h"

namespace tread_wear {

std::string nodeHelp() {
  return std::string(
             "usage: tread_wear_node [--help] [__name:=NAME] [__ns:=NAMESPACE] [TOPIC:=NEW_TOPIC ...]\n"
             "Live tire tread wear per wheel from the brush model (docs/node.md). Needs a ROS master; reads its\n"
             "parameters from its private namespace (launch/tread_wear.launch loads config/vehicle_wheels.yaml).\n"
             "\n"
             "Parameters (~key [unit] = default: meaning):\n") +
         nodeConfigKeysHelp() +
         "\n"
         "Topics (relative to the node's namespace; <name> = wheel name):\n"
         "  in   wheels/<name>/load               tread_wear/WheelLoad         load_n [N]\n"
         "  in   wheels/<name>/slip               tread_wear/WheelSlip         slip_angle_rad [rad], slip_ratio [-], "
         "path_curvature_per_m [1/m]\n"
         "  in   wheels/<name>/speed              tread_wear/WheelSpeed        speed_mps [m/s]\n"
         "  in   wheels/<name>/tread_temperature  tread_wear/TreadTemperature  temperature_c [degC] (optional)\n"
         "  out  wheels/<name>/wear               tread_wear/WheelWear         per wheel, every update\n"
         "  out  wear                             tread_wear/VehicleWear       all wheels and totals, every update\n"
         "  out  wear_markers                     visualization_msgs/MarkerArray  contact patches, marker_rate_hz\n"
         "  out  /diagnostics                     diagnostic_msgs/DiagnosticArray  wheels, vehicle, update loop, persistence\n"
         "  out  input_progress (sim time)        tread_wear/InputProgress     inputs processed up to its stamp, for a "
         "rate-controlled rosbag play (launch/replay.launch)\n"
         "  out  /tf_static                       tf2_msgs/TFMessage           base_frame -> wheels with position_m\n"
         "  out  wear_map (latched)               tread_wear/PlannerWearMap    per-wheel wear map over (v, a_x, a_y) "
         "for planners, rebuilt on a preset or tread temperature change\n"
         "\n"
         "Services:\n"
         "  evaluate_wear   tread_wear/EvaluateWear  wear and forces of hypothetical states of one wheel (planner)\n"
         "  reset_wheel     tread_wear/ResetWheel    tire change: zero a wheel's loss, record the new tire id\n"
         "  evaluate_trajectories  tread_wear/EvaluateTrajectories  wear cost of candidate vehicle trajectories "
         "(planner; mode map or direct; docs/planner.md)\n"
         "  ~set_parameters dynamic_reconfigure      update_rate_hz, budget_us, preset (checked as at start-up)\n"
         "\n"
         "Planner keys (~planner/...; config/vehicle_wheels.yaml): vehicle_params [path] (empty = planner off),\n"
         "wheel_names [4 names] = front_left front_right rear_left rear_right, build_map = true,\n"
         "map_temperature_step_c [K] = 5, max_path_curvature_per_m [1/m] = 0.25, map_threads = 1\n"
         "\n"
         "Replay key (simulated time): ~replay_resume_service [service name] = \"\" : a paused rosbag play's pause service\n"
         "(std_srvs/SetBool), called to resume it once every required input is connected (replay.launch sets\n"
         "/player/pause_playback).\n";
}

}  // namespace tread_wear
