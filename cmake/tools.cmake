# Offline command-line tools: src/tools/<name>_main.cpp -> tread_wear_<name>, mains of a few lines over the cli
# module; the rosbag tools (drive, replay) and tread_wear_diagnose's --bag also link the ros/bag module.
file(GLOB TREAD_WEAR_TOOL_MAINS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/tools/*_main.cpp)
foreach(main ${TREAD_WEAR_TOOL_MAINS})
  get_filename_component(name ${main} NAME_WE)
  string(REGEX REPLACE "_main$" "" name ${name})
  add_executable(tread_wear_${name} ${main})
  target_link_libraries(tread_wear_${name} tread_wear_cli)
  install(TARGETS tread_wear_${name} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()
foreach(tool drive replay diagnose)
  target_link_libraries(tread_wear_${tool} tread_wear_ros_bag)
endforeach()
target_compile_definitions(tread_wear_diagnose PRIVATE
                           TREAD_WEAR_PLOT_SCRIPT="${PROJECT_SOURCE_DIR}/scripts/plot_diagnosis.py")
target_compile_definitions(tread_wear_drive PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")
target_compile_definitions(tread_wear_replay PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")
