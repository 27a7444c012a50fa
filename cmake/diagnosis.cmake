# Mismatch diagnosis tools. tread_wear_diagnose, tread_wear_conceal and tread_wear_diagnosis_harness come from the
# generic tools glob (cmake/tools.cmake); this fragment points tread_wear_diagnose at the plotting script and, when
# the rosbag tools are built (cmake/drive.cmake), adds the bag adapter (src/tools/ros/diagnosis_bag.cpp) for --bag.
if(TARGET tread_wear_diagnose)
  target_compile_definitions(tread_wear_diagnose PRIVATE
                             TREAD_WEAR_PLOT_SCRIPT="${PROJECT_SOURCE_DIR}/scripts/plot_diagnosis.py")
  if(TARGET tread_wear_bag_io)
    add_library(tread_wear_diagnosis_bag STATIC ${PROJECT_SOURCE_DIR}/src/tools/ros/diagnosis_bag.cpp)
    target_link_libraries(tread_wear_diagnosis_bag PUBLIC tread_wear_bag_io)
    add_dependencies(tread_wear_diagnosis_bag ${PROJECT_NAME}_generate_messages_cpp)
    target_link_libraries(tread_wear_diagnose tread_wear_diagnosis_bag)
    target_compile_definitions(tread_wear_diagnose PRIVATE TREAD_WEAR_DIAGNOSIS_ROSBAG)
    if(CATKIN_ENABLE_TESTING)
      tread_wear_add_gtest(test_diagnosis_bag ${PROJECT_SOURCE_DIR}/test/ros/test_diagnosis_bag.cpp
                           tread_wear_diagnosis_bag)
      target_compile_definitions(test_diagnosis_bag PRIVATE
                                 TREAD_WEAR_PYTHON_PATH="${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_PYTHON_DESTINATION}")
    endif()
  endif()
endif()
