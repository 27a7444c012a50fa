# Benchmarks and accuracy tables of the wear-model presets (docs/performance.md); only with Google Benchmark, a test
# dependency, hence with the tests (CMakeLists.txt includes this file under CATKIN_ENABLE_TESTING). Both read nothing
# from the source tree and are installed with the tools: `rosrun tread_wear tread_wear_bench` measures the cost of a
# wheel evaluation on the computer that runs the node.
find_package(benchmark QUIET)
if(benchmark_FOUND)
  add_executable(${PROJECT_NAME}_bench bench/wear_model_bench.cpp)
  target_link_libraries(${PROJECT_NAME}_bench ${PROJECT_NAME}_cli benchmark::benchmark)
  add_executable(${PROJECT_NAME}_accuracy bench/accuracy_main.cpp)
  target_link_libraries(${PROJECT_NAME}_accuracy ${PROJECT_NAME}_cli)
  # The planner's wear cost (docs/planner.md): map build, batch of 100 x 100 from the map and direct, map error. It
  # reads the passenger car's files from $TREAD_WEAR_CONFIG_DIR, else from this source tree's config/.
  add_executable(${PROJECT_NAME}_planner_bench bench/planner_bench.cpp)
  target_link_libraries(${PROJECT_NAME}_planner_bench ${PROJECT_NAME}_cli benchmark::benchmark)
  target_compile_definitions(${PROJECT_NAME}_planner_bench PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")
  install(TARGETS ${PROJECT_NAME}_accuracy ${PROJECT_NAME}_bench ${PROJECT_NAME}_planner_bench
          RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
else()
  message(STATUS "Google Benchmark not found: ${PROJECT_NAME}_bench and ${PROJECT_NAME}_accuracy are not built")
endif()
# A month of driving as one bag, for timing the diagnosis of drives (docs/diagnosis.md, "Drives between
# measurements"); reads the passenger car's files from this source tree.
add_executable(${PROJECT_NAME}_month_bench bench/month_of_driving.cpp)
target_link_libraries(${PROJECT_NAME}_month_bench ${PROJECT_NAME}_ros_bag ${PROJECT_NAME}_cli)
target_compile_definitions(${PROJECT_NAME}_month_bench PRIVATE TREAD_WEAR_SHARE_DIR="${PROJECT_SOURCE_DIR}")
install(TARGETS ${PROJECT_NAME}_month_bench RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
