# ROS layer: tread_wear_ros (config, node wrapper, markers) and the thin tread_wear_node main.
file(GLOB TREAD_WEAR_ROS_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/ros/*.cpp)
add_library(tread_wear_ros ${TREAD_WEAR_ROS_SOURCES})
target_include_directories(tread_wear_ros PUBLIC ${PROJECT_SOURCE_DIR}/include ${CATKIN_DEVEL_PREFIX}/include
                           ${catkin_INCLUDE_DIRS})
target_link_libraries(tread_wear_ros PUBLIC tread_wear_core ${catkin_LIBRARIES})
add_dependencies(tread_wear_ros ${PROJECT_NAME}_generate_messages_cpp ${PROJECT_NAME}_gencfg)

add_executable(tread_wear_node src/nodes/tread_wear_node.cpp)
target_link_libraries(tread_wear_node tread_wear_ros)
install(TARGETS tread_wear_ros tread_wear_node ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
        LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(PROGRAMS scripts/rviz_screenshot.sh DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION} OPTIONAL)
