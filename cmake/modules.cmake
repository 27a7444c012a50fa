# One library per module (docs/architecture.md): src/<module>/*.cpp -> tread_wear_<module> ("/" -> "_"), public
# headers in include/tread_wear/<module>/. Each module links only the modules and external libraries that its line
# of the map allows; none of the modules below includes a ROS header. The library is installed to lib/ and exported
# by catkin_package (CMakeLists.txt); the source tree's include directory is on its interface only while building.
#catkin_lint: ignore_once literal_project_name
function(tread_wear_module name)
  cmake_parse_arguments(M "" "" "MODULES;PUBLIC;PRIVATE" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  string(REPLACE "/" "_" target ${PROJECT_NAME}_${name})
  list(TRANSFORM M_MODULES PREPEND ${PROJECT_NAME}_)
  add_library(${target} ${sources})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>)
  target_link_libraries(${target} PUBLIC ${M_MODULES} ${M_PUBLIC} PRIVATE ${M_PRIVATE})
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  install(TARGETS ${target} ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
          LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endfunction()

tread_wear_module(model PUBLIC Eigen3::Eigen)
tread_wear_module(reference MODULES model
                  PRIVATE SUNDIALS::cvode SUNDIALS::nvecserial SUNDIALS::sunlinsoldense SUNDIALS::sunmatrixdense)
tread_wear_module(vehicle MODULES model)
tread_wear_module(estimation MODULES model vehicle)
tread_wear_module(planning MODULES model vehicle estimation)
tread_wear_module(io MODULES model vehicle estimation PUBLIC nlohmann_json::nlohmann_json PRIVATE yaml-cpp)
tread_wear_module(pipeline MODULES model estimation io)
tread_wear_module(fitting MODULES model io PRIVATE Ceres::ceres)
tread_wear_module(diagnosis MODULES model io fitting PRIVATE Boost::headers muparser::muparser)
# The diagnosis's proving grounds: concealed-effect generators, drive fleets, the harness, detectability reference.
tread_wear_module(proving MODULES model vehicle estimation io diagnosis)
tread_wear_module(report MODULES io fitting diagnosis proving PUBLIC nlohmann_json::nlohmann_json)
tread_wear_module(studies MODULES model reference io)
tread_wear_module(cli MODULES model reference vehicle planning io fitting diagnosis proving report studies)

# The marcher's x step on SIMD packs of strips with glibc's libmvec vector exp/log: four strips per AVX2 + FMA
# pack (src/model/brush_march_avx2.cpp, compiled for AVX2, chosen at run time on CPUs that have it), else two
# per SSE2 pack (the x86-64 baseline). Elsewhere, or with the option off, the strips run one at a time.
#catkin_lint: ignore_once global_var_collision
option(TREAD_WEAR_SIMD_MARCHER "SIMD marcher kernels (x86-64 with glibc libmvec)" ON)
find_library(TREAD_WEAR_MVEC_LIBRARY mvec)
set(TREAD_WEAR_SIMD_SOURCES ${PROJECT_SOURCE_DIR}/src/model/brush_march_avx2.cpp
    ${PROJECT_SOURCE_DIR}/src/model/brush_march_sse2.cpp)
if(TREAD_WEAR_SIMD_MARCHER AND CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$" AND TREAD_WEAR_MVEC_LIBRARY)
  set_source_files_properties(${PROJECT_SOURCE_DIR}/src/model/brush_march_avx2.cpp PROPERTIES COMPILE_OPTIONS
                              "-mavx2;-mfma")
  target_compile_definitions(${PROJECT_NAME}_model PRIVATE TREAD_WEAR_SIMD_MARCHER)
  target_link_libraries(${PROJECT_NAME}_model PRIVATE ${TREAD_WEAR_MVEC_LIBRARY})
  message(STATUS "${PROJECT_NAME}: SIMD marcher kernels on (${TREAD_WEAR_MVEC_LIBRARY})")
else()
  set_source_files_properties(${TREAD_WEAR_SIMD_SOURCES} PROPERTIES HEADER_FILE_ONLY ON)
  message(STATUS "${PROJECT_NAME}: SIMD marcher kernels off (strips one at a time)")
endif()

install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
install(DIRECTORY config data launch DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
