# tread_wear_core: the model, calibration and diagnosis. No ROS header may be included here.
file(GLOB TREAD_WEAR_CORE_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/core/*.cpp)
add_library(tread_wear_core ${TREAD_WEAR_CORE_SOURCES})
target_include_directories(tread_wear_core PUBLIC ${PROJECT_SOURCE_DIR}/include ${EIGEN3_INCLUDE_DIR})
target_link_libraries(tread_wear_core PUBLIC SUNDIALS::cvode SUNDIALS::nvecserial SUNDIALS::sunlinsoldense
                      SUNDIALS::sunmatrixdense yaml-cpp nlohmann_json::nlohmann_json)
set_target_properties(tread_wear_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
install(TARGETS tread_wear_core ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
        LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY include/${PROJECT_NAME}/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})
install(DIRECTORY config data launch DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION} OPTIONAL)
# Bounded nonlinear least squares for calibration (least_squares.h): Ceres Solver (Debian libceres-dev).
find_package(Ceres REQUIRED)
target_link_libraries(tread_wear_core PUBLIC Ceres::ceres)
# Noncentral F distribution of the diagnosis's detectability reference: Boost.Math (header-only, Debian libboost-dev).
find_package(Boost REQUIRED)
target_link_libraries(tread_wear_core PRIVATE Boost::headers)
# The marcher's x step on SIMD packs of strips with glibc's libmvec vector exp/log: four strips per AVX2 + FMA
# pack (src/core/brush_march_avx2.cpp, compiled for AVX2, chosen at run time on CPUs that have it), else two
# per SSE2 pack (the x86-64 baseline). Elsewhere, or with the option off, the strips run one at a time.
option(TREAD_WEAR_SIMD_MARCHER "SIMD marcher kernels (x86-64 with glibc libmvec)" ON)
find_library(TREAD_WEAR_MVEC_LIBRARY mvec)
set(TREAD_WEAR_SIMD_SOURCES ${PROJECT_SOURCE_DIR}/src/core/brush_march_avx2.cpp
    ${PROJECT_SOURCE_DIR}/src/core/brush_march_sse2.cpp)
if(TREAD_WEAR_SIMD_MARCHER AND CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$" AND TREAD_WEAR_MVEC_LIBRARY)
  set_source_files_properties(${PROJECT_SOURCE_DIR}/src/core/brush_march_avx2.cpp PROPERTIES COMPILE_OPTIONS
                              "-mavx2;-mfma")
  target_compile_definitions(tread_wear_core PRIVATE TREAD_WEAR_SIMD_MARCHER)
  target_link_libraries(tread_wear_core PRIVATE ${TREAD_WEAR_MVEC_LIBRARY})
  message(STATUS "tread_wear: SIMD marcher kernels on (${TREAD_WEAR_MVEC_LIBRARY})")
else()
  set_source_files_properties(${TREAD_WEAR_SIMD_SOURCES} PROPERTIES HEADER_FILE_ONLY ON)
  message(STATUS "tread_wear: SIMD marcher kernels off (strips one at a time)")
endif()

# A GoogleTest binary over the given libraries, registered with ctest by catkin and built by default (build + ctest
# suffice), run from the source tree, which it knows as TREAD_WEAR_SOURCE_DIR. Used by cmake/tests.cmake and the
# tool fragments that test their rosbag parts (drive.cmake, diagnosis.cmake).
function(tread_wear_add_gtest name source)
  catkin_add_gtest(${name} ${source} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} ${ARGN} GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE TREAD_WEAR_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL OFF)
endfunction()
