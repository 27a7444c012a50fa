# Node tests through a running ROS graph (rostest starts its own master per .test file). One gtest binary,
# each .test file selects its cases with --gtest_filter.
find_package(rostest REQUIRED)
add_rostest_gtest(test_tread_wear_node test/ros/node.test test/ros/test_node.cpp)
target_link_libraries(test_tread_wear_node tread_wear_io ${catkin_LIBRARIES})
target_include_directories(test_tread_wear_node PRIVATE ${PROJECT_SOURCE_DIR}/include ${CATKIN_DEVEL_PREFIX}/include
                           ${catkin_INCLUDE_DIRS})
target_compile_definitions(test_tread_wear_node PRIVATE TREAD_WEAR_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                           TREAD_WEAR_NODE_BINARY="$<TARGET_FILE:tread_wear_node>")
add_dependencies(test_tread_wear_node ${PROJECT_NAME}_generate_messages_cpp tread_wear_node)
set_target_properties(test_tread_wear_node PROPERTIES EXCLUDE_FROM_ALL OFF)
add_rostest(test/ros/time_jump.test DEPENDENCIES test_tread_wear_node)
add_rostest(test/ros/persistence.test DEPENDENCIES test_tread_wear_node)
add_rostest(test/ros/bag.test DEPENDENCIES test_tread_wear_node)
# The node's parts alone, without a master (test/ros/test_node_parts.cpp); its --help case runs the node binary.
tread_wear_add_gtest(test_node_parts ${PROJECT_SOURCE_DIR}/test/ros/test_node_parts.cpp ${PROJECT_NAME}_ros)
target_compile_definitions(test_node_parts PRIVATE TREAD_WEAR_NODE_BINARY="$<TARGET_FILE:${PROJECT_NAME}_node>")
add_dependencies(test_node_parts ${PROJECT_NAME}_node)
