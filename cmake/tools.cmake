# Offline command-line tools: src/tools/<name>_main.cpp -> tread_wear_<name>, thin mains over the core.
file(GLOB TREAD_WEAR_TOOL_MAINS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/tools/*_main.cpp)
foreach(main ${TREAD_WEAR_TOOL_MAINS})
  get_filename_component(name ${main} NAME_WE)
  string(REGEX REPLACE "_main$" "" name ${name})
  add_executable(tread_wear_${name} ${main})
  target_link_libraries(tread_wear_${name} tread_wear_core)
  install(TARGETS tread_wear_${name} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()
