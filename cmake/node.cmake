# ROS layer: tread_wear_ros (node parts over model + estimation + io), tread_wear_ros_bag (rosbag records check,
# drive and diagnosis bags) and the thin tread_wear_node main.
function(tread_wear_ros_module name)
  tread_wear_module(${name} ${ARGN})
  string(REPLACE "/" "_" target tread_wear_${name})
  target_include_directories(${target} PUBLIC ${catkin_INCLUDE_DIRS}
                             $<BUILD_INTERFACE:${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_INCLUDE_DESTINATION}>)
  target_link_libraries(${target} PUBLIC ${catkin_LIBRARIES})
  add_dependencies(${target} ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)
endfunction()

tread_wear_ros_module(ros MODULES model estimation io)
# rosbag's own codecs, so that the bag check can decompress a chunk before rosbag parses it (checkBagRecords).
find_package(BZip2 REQUIRED)
find_package(roslz4 REQUIRED)
tread_wear_ros_module(ros/bag MODULES model vehicle estimation io cli PRIVATE BZip2::BZip2 ${roslz4_LIBRARIES})
target_include_directories(tread_wear_ros_bag PRIVATE ${roslz4_INCLUDE_DIRS})

add_executable(tread_wear_node src/nodes/tread_wear_node.cpp)
target_link_libraries(tread_wear_node tread_wear_ros)
install(TARGETS tread_wear_node RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(PROGRAMS scripts/rviz_screenshot.sh DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
