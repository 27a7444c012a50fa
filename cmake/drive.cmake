# Test drives: tread_wear_drive (generator) and tread_wear_replay (offline replay), over the core library plus
# rosbag. Their mains live in src/tools/ros/ so the generic tools glob (src/tools/*_main.cpp) does not take them.
# rosbag's own codecs, so that the bag check can decompress a chunk before rosbag parses it (checkBagRecords).
find_package(BZip2 REQUIRED)
find_package(roslz4 REQUIRED)
add_library(tread_wear_bag_io STATIC ${PROJECT_SOURCE_DIR}/src/tools/ros/bag_io.cpp)
target_include_directories(tread_wear_bag_io PUBLIC ${PROJECT_SOURCE_DIR}/src/tools/ros ${PROJECT_SOURCE_DIR}/include
                           ${CATKIN_DEVEL_PREFIX}/include ${catkin_INCLUDE_DIRS})
target_include_directories(tread_wear_bag_io PRIVATE ${roslz4_INCLUDE_DIRS})
target_link_libraries(tread_wear_bag_io PUBLIC tread_wear_core ${catkin_LIBRARIES} PRIVATE BZip2::BZip2 ${roslz4_LIBRARIES})
add_dependencies(tread_wear_bag_io ${PROJECT_NAME}_generate_messages_cpp)
set_target_properties(tread_wear_bag_io PROPERTIES POSITION_INDEPENDENT_CODE ON)

foreach(tool drive replay)
  add_executable(tread_wear_${tool} ${PROJECT_SOURCE_DIR}/src/tools/ros/${tool}_main.cpp)
  target_link_libraries(tread_wear_${tool} tread_wear_bag_io)
  target_compile_definitions(tread_wear_${tool} PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")
  install(TARGETS tread_wear_${tool} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()

if(CATKIN_ENABLE_TESTING)
  tread_wear_add_gtest(test_drive_replay ${PROJECT_SOURCE_DIR}/test/ros/test_drive_replay.cpp tread_wear_bag_io)
  target_compile_definitions(test_drive_replay PRIVATE TREAD_WEAR_REPLAY_BINARY="$<TARGET_FILE:tread_wear_replay>")
  add_dependencies(test_drive_replay tread_wear_replay)
endif()
