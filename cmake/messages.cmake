# Messages and services; included before catkin_package() as catkin requires.
add_message_files(FILES InputProgress.msg TreadTemperature.msg VehicleWear.msg WheelInputQuality.msg WheelLoad.msg WheelSlip.msg
                  WheelSpeed.msg WheelState.msg WheelWear.msg WheelWearRate.msg
                  PlannerWearMap.msg Trajectory.msg TrajectoryWearCost.msg)
add_service_files(FILES EvaluateWear.srv ResetWheel.srv EvaluateTrajectories.srv)
generate_dynamic_reconfigure_options(cfg/TreadWear.cfg)
generate_messages(DEPENDENCIES std_msgs)
