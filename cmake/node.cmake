# ROS layer: tread_wear_ros (node parts over model + estimation + io + pipeline), tread_wear_ros_bag (rosbag records check,
# drive and diagnosis bags) and the thin tread_wear_node main.
# From here on, every target of this directory compiles against the package's headers (also on each module's
# interface) and the ROS packages' headers (catkin_INCLUDE_DIRS; the ROS-free modules above do not). The headers
# generated from msg/, srv/ and cfg/ come through catkin: gencpp and dynamic_reconfigure put the devel space's include
# directory on this directory's include path, and catkin_package exports it (devel space) or installs the headers to
# include/tread_wear/ (install space).
include_directories(include ${catkin_INCLUDE_DIRS})

# A ROS module: a module (cmake/modules.cmake) that also links the ROS packages and is built after the message and
# dynamic_reconfigure headers.
#catkin_lint: ignore_once literal_project_name
function(tread_wear_ros_module name)
  tread_wear_module(${name} ${ARGN})
  string(REPLACE "/" "_" target ${PROJECT_NAME}_${name})
  target_link_libraries(${target} PUBLIC ${catkin_LIBRARIES})
  add_dependencies(${target} ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)
endfunction()

tread_wear_ros_module(ros MODULES model estimation planning io pipeline)
# rosbag's own codecs, so that the bag check can decompress a chunk before rosbag parses it (checkBagRecords).
find_package(BZip2 REQUIRED)
find_package(roslz4 REQUIRED)
tread_wear_ros_module(ros/bag MODULES model vehicle estimation io cli PRIVATE BZip2::BZip2 ${roslz4_LIBRARIES})
target_include_directories(${PROJECT_NAME}_ros_bag PRIVATE ${roslz4_INCLUDE_DIRS})

add_executable(${PROJECT_NAME}_node src/nodes/tread_wear_node.cpp)
target_link_libraries(${PROJECT_NAME}_node ${PROJECT_NAME}_ros)
install(TARGETS ${PROJECT_NAME}_node RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
# The vehicle front end (docs/vehicle_inputs_node.md): sensor_msgs, nav_msgs and tf2 headers in ros/vehicle_inputs_*.
find_package(sensor_msgs REQUIRED)
find_package(nav_msgs REQUIRED)
find_package(tf2_msgs REQUIRED)  # package.xml's build_depend (ros/bag's /tf_static records); headers in /usr/include
target_include_directories(${PROJECT_NAME}_ros PRIVATE ${sensor_msgs_INCLUDE_DIRS} ${nav_msgs_INCLUDE_DIRS})
add_executable(vehicle_inputs_node src/nodes/vehicle_inputs_node.cpp)
target_include_directories(vehicle_inputs_node PRIVATE ${sensor_msgs_INCLUDE_DIRS} ${nav_msgs_INCLUDE_DIRS})
target_link_libraries(vehicle_inputs_node ${PROJECT_NAME}_ros)
install(TARGETS vehicle_inputs_node RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
