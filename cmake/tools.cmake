# Offline command-line tools: src/tools/<name>_main.cpp -> tread_wear_<name>, mains of a few lines over the cli
# module; the rosbag tools (drive, replay, vehicle_inputs) and the --bag of tread_wear_diagnose and tread_wear_conceal
# also link the ros/bag module.
file(GLOB TREAD_WEAR_TOOL_MAINS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/tools/*_main.cpp)
foreach(main ${TREAD_WEAR_TOOL_MAINS})
  get_filename_component(name ${main} NAME_WE)
  string(REGEX REPLACE "_main$" "" name ${name})
  add_executable(${PROJECT_NAME}_${name} ${main})
  target_link_libraries(${PROJECT_NAME}_${name} ${PROJECT_NAME}_cli)
  install(TARGETS ${PROJECT_NAME}_${name} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()
foreach(tool drive replay diagnose conceal vehicle_inputs)
  target_link_libraries(${PROJECT_NAME}_${tool} ${PROJECT_NAME}_ros_bag)
endforeach()
target_compile_definitions(${PROJECT_NAME}_diagnose PRIVATE
                           TREAD_WEAR_PLOT_SCRIPT="${PROJECT_SOURCE_DIR}/scripts/plot_diagnosis.py")
target_compile_definitions(${PROJECT_NAME}_drive PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")
target_compile_definitions(${PROJECT_NAME}_replay PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")
target_compile_definitions(${PROJECT_NAME}_vehicle_inputs PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")

# Python tools, installed next to the C++ ones (rosrun tread_wear <name>.py; catkin_install_python points their first
# line at catkin's python): the synthetic input publisher, the plots of the tools' outputs and the grid checks (which
# run tread_wear_eval from TREAD_WEAR_BIN), and the fleet's commands over Dask (python/tread_wear_fleet, docs/fleet.md).
catkin_install_python(PROGRAMS scripts/grid_convergence.py scripts/plot_diagnosis.py scripts/plot_drive.py
                      scripts/plot_wear_characteristics.py scripts/publish_wheel_inputs.py scripts/replay_done.py
                      scripts/wltc_grid_check.py scripts/tread_wear_fleet scripts/tread_wear_fleet_generate
                      DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
# Not installed: the repository's own workflows, which run from a checkout (they change to the repository root, read
# config/, data/ and examples/ there, and use a build directory such as _build): scripts/*.sh (main job, tests,
# sanitizers, output comparison with its helper scripts/compare_outputs.py, sensitivity, rviz screenshot),
# bench/node_cpu.sh and bench/replay_live_vs_offline.py. catkin_lint has no per-file exception, so its check for
# executable files that are not installed is off for the whole package: add a new script meant for rosrun to the
# list above.
#catkin_lint: ignore uninstalled_script
