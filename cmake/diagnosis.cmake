# Mismatch diagnosis tools. tread_wear_diagnose, tread_wear_conceal and tread_wear_diagnosis_harness come from the
# generic tools glob (cmake/tools.cmake); this fragment points tread_wear_diagnose at the plotting script and, when
# catkin's rosbag is available, adds the bag adapter (src/tools/ros/diagnosis_bag.cpp) for --bag.
if(TARGET tread_wear_diagnose)
  target_compile_definitions(tread_wear_diagnose PRIVATE
                             TREAD_WEAR_PLOT_SCRIPT="${PROJECT_SOURCE_DIR}/scripts/plot_diagnosis.py")
  if(rosbag_FOUND)
    target_sources(tread_wear_diagnose PRIVATE ${PROJECT_SOURCE_DIR}/src/tools/ros/diagnosis_bag.cpp)
    target_include_directories(tread_wear_diagnose PRIVATE ${PROJECT_SOURCE_DIR}/src/tools
                               ${CATKIN_DEVEL_PREFIX}/include ${catkin_INCLUDE_DIRS})
    target_link_libraries(tread_wear_diagnose ${catkin_LIBRARIES})
    target_compile_definitions(tread_wear_diagnose PRIVATE TREAD_WEAR_DIAGNOSIS_ROSBAG)
    add_dependencies(tread_wear_diagnose ${PROJECT_NAME}_generate_messages_cpp)
  endif()
endif()
