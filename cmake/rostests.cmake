# Node tests through a running ROS graph (rostest starts its own master per .test file). One gtest binary
# (test_tread_wear_node), each .test file selects its cases with --gtest_filter.
find_package(rostest REQUIRED)
add_rostest_gtest(test_${PROJECT_NAME}_node test/ros/node.test test/ros/test_node.cpp)
target_link_libraries(test_${PROJECT_NAME}_node ${PROJECT_NAME}_io ${catkin_LIBRARIES} nlohmann_json::nlohmann_json)
target_compile_definitions(test_${PROJECT_NAME}_node PRIVATE TREAD_WEAR_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                           TREAD_WEAR_NODE_BINARY="$<TARGET_FILE:${PROJECT_NAME}_node>")
add_dependencies(test_${PROJECT_NAME}_node ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_node)
set_target_properties(test_${PROJECT_NAME}_node PROPERTIES EXCLUDE_FROM_ALL OFF)
add_rostest(test/ros/time_jump.test DEPENDENCIES test_${PROJECT_NAME}_node)
add_rostest(test/ros/persistence.test DEPENDENCIES test_${PROJECT_NAME}_node)
add_rostest(test/ros/bag.test DEPENDENCIES test_${PROJECT_NAME}_node)
add_rostest(test/ros/unintegrated_time.test DEPENDENCIES test_${PROJECT_NAME}_node)
# The fast replay's drive bag (the first 300 s of the WLTC) and its offline replay, made once at build time so the
# rostest only plays it: replay.launch at rate 100 against tread_wear_replay on the same bag.
set(TREAD_WEAR_FAST_REPLAY_BAG ${CMAKE_CURRENT_BINARY_DIR}/test_data/wltc_first_300s.bag)
set(TREAD_WEAR_FAST_REPLAY_SUMMARY ${CMAKE_CURRENT_BINARY_DIR}/test_data/wltc_first_300s_offline.json)
add_custom_command(
  OUTPUT ${TREAD_WEAR_FAST_REPLAY_BAG} ${TREAD_WEAR_FAST_REPLAY_SUMMARY}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/test_data
  COMMAND $<TARGET_FILE:${PROJECT_NAME}_drive> --profile ${PROJECT_SOURCE_DIR}/test/ros/wltc_first_300s.csv
          --out ${TREAD_WEAR_FAST_REPLAY_BAG}
  COMMAND $<TARGET_FILE:${PROJECT_NAME}_replay> ${TREAD_WEAR_FAST_REPLAY_BAG} --quiet
          --summary ${TREAD_WEAR_FAST_REPLAY_SUMMARY}
  DEPENDS ${PROJECT_NAME}_drive ${PROJECT_NAME}_replay ${PROJECT_SOURCE_DIR}/test/ros/wltc_first_300s.csv
          ${PROJECT_SOURCE_DIR}/config/vehicle_wheels.yaml
  COMMENT "fast replay test data: 300 s drive bag and its offline replay"
  VERBATIM)
add_custom_target(${PROJECT_NAME}_fast_replay_data ALL
                  DEPENDS ${TREAD_WEAR_FAST_REPLAY_BAG} ${TREAD_WEAR_FAST_REPLAY_SUMMARY})
add_rostest(test/ros/fast_replay.test DEPENDENCIES test_${PROJECT_NAME}_node ${PROJECT_NAME}_fast_replay_data
            ARGS data_dir:=${CMAKE_CURRENT_BINARY_DIR}/test_data)
# The node's parts alone, without a master (test/ros/test_node_parts.cpp); its --help case runs the node binary.
tread_wear_add_gtest(test_node_parts ${PROJECT_SOURCE_DIR}/test/ros/test_node_parts.cpp ${PROJECT_NAME}_ros)
target_compile_definitions(test_node_parts PRIVATE TREAD_WEAR_NODE_BINARY="$<TARGET_FILE:${PROJECT_NAME}_node>")
add_dependencies(test_node_parts ${PROJECT_NAME}_node)
# vehicle_inputs_node (docs/vehicle_inputs_node.md): the synthetic-sensor rostests and its parts without a master.
add_rostest_gtest(test_vehicle_inputs test/ros/vehicle_inputs.test test/ros/test_vehicle_inputs.cpp)
target_link_libraries(test_vehicle_inputs ${PROJECT_NAME}_io ${catkin_LIBRARIES})
add_dependencies(test_vehicle_inputs ${PROJECT_NAME}_generate_messages_cpp vehicle_inputs_node)
set_target_properties(test_vehicle_inputs PROPERTIES EXCLUDE_FROM_ALL OFF)
add_rostest(test/ros/vehicle_inputs_no_tf.test DEPENDENCIES test_vehicle_inputs)
add_rostest(test/ros/vehicle_inputs_time_jump.test DEPENDENCIES test_vehicle_inputs)
# The node and the tool on one bag (the test writes it and runs the tool in-process; rosbag play to the node).
add_rostest_gtest(test_vehicle_inputs_bag_play test/ros/vehicle_inputs_bag.test test/ros/test_vehicle_inputs_bag_play.cpp)
target_link_libraries(test_vehicle_inputs_bag_play ${PROJECT_NAME}_ros_bag ${catkin_LIBRARIES})
target_compile_definitions(test_vehicle_inputs_bag_play PRIVATE TREAD_WEAR_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
add_dependencies(test_vehicle_inputs_bag_play ${PROJECT_NAME}_generate_messages_cpp vehicle_inputs_node)
set_target_properties(test_vehicle_inputs_bag_play PROPERTIES EXCLUDE_FROM_ALL OFF)
tread_wear_add_gtest(test_vehicle_inputs_parts ${PROJECT_SOURCE_DIR}/test/ros/test_vehicle_inputs_parts.cpp
                     ${PROJECT_NAME}_ros)
# The planner at the vehicle level (evaluate_trajectories, wear_map) without a master.
tread_wear_add_gtest(test_node_planner ${PROJECT_SOURCE_DIR}/test/ros/test_node_planner.cpp ${PROJECT_NAME}_ros)
