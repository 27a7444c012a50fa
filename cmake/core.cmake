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
