# A GoogleTest binary over the given libraries, registered with ctest by catkin and built by default (build + ctest
# suffice), run from the source tree, which it knows as TREAD_WEAR_SOURCE_DIR. Each test binary gets its own
# temporary directory (TEST_TMPDIR, which ::testing::TempDir() returns) in the build tree, so that tests running at
# once (ctest -j, or two checkouts on one machine) never write the same file.
#catkin_lint: ignore_once literal_project_name
function(tread_wear_add_gtest name source)
  catkin_add_gtest(${name} ${source} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set(tmp_dir ${CMAKE_CURRENT_BINARY_DIR}/test_tmp/${name})
  file(MAKE_DIRECTORY ${tmp_dir})
  set_tests_properties(_ctest_${PROJECT_NAME}_gtest_${name} PROPERTIES ENVIRONMENT "TEST_TMPDIR=${tmp_dir}")
  target_link_libraries(${name} ${ARGN} GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/test)
  target_compile_definitions(${name} PRIVATE TREAD_WEAR_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL OFF)
endfunction()

# Tests mirror the modules: test/<module>/test_<name>.cpp -> one gtest binary each (test/paper: the paper's
# tables), built by default so that build + ctest suffice. ROS-free tests link the cli module, which carries every
# ROS-free module; test/common holds their shared helpers. ROS tests: test/ros (rostest) and test/ros/bag.
file(GLOB TREAD_WEAR_TEST_DIRS LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/test/*)
foreach(dir ${TREAD_WEAR_TEST_DIRS})
  get_filename_component(module ${dir} NAME)
  if(NOT IS_DIRECTORY ${dir} OR module STREQUAL "ros" OR module STREQUAL "common")
    continue()
  endif()
  file(GLOB tests CONFIGURE_DEPENDS ${dir}/test_*.cpp)
  foreach(src ${tests})
    get_filename_component(name ${src} NAME_WE)
    tread_wear_add_gtest(${name} ${src} ${PROJECT_NAME}_cli)
    target_compile_definitions(${name} PRIVATE TREAD_WEAR_BINARY_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
  endforeach()
endforeach()

tread_wear_add_gtest(test_drive_replay ${PROJECT_SOURCE_DIR}/test/ros/bag/test_drive_replay.cpp ${PROJECT_NAME}_ros_bag)
target_compile_definitions(test_drive_replay PRIVATE TREAD_WEAR_REPLAY_BINARY="$<TARGET_FILE:${PROJECT_NAME}_replay>")
add_dependencies(test_drive_replay ${PROJECT_NAME}_replay)
tread_wear_add_gtest(test_drive_scenarios ${PROJECT_SOURCE_DIR}/test/ros/bag/test_drive_scenarios.cpp
                     ${PROJECT_NAME}_ros_bag)
tread_wear_add_gtest(test_vehicle_inputs_bag ${PROJECT_SOURCE_DIR}/test/ros/bag/test_vehicle_inputs_bag.cpp
                     ${PROJECT_NAME}_ros_bag)
tread_wear_add_gtest(test_drive_integration ${PROJECT_SOURCE_DIR}/test/ros/bag/test_drive_integration.cpp
                     ${PROJECT_NAME}_ros_bag ${PROJECT_NAME}_cli)
tread_wear_add_gtest(test_diagnosis_bag ${PROJECT_SOURCE_DIR}/test/ros/bag/test_diagnosis_bag.cpp
                     ${PROJECT_NAME}_ros_bag ${PROJECT_NAME}_cli)
target_compile_definitions(test_diagnosis_bag PRIVATE
                           TREAD_WEAR_PYTHON_PATH="${CATKIN_DEVEL_PREFIX}/${CATKIN_GLOBAL_PYTHON_DESTINATION}")
# The test writes its bag with the example's python script, which imports the generated python messages.
add_dependencies(test_diagnosis_bag ${PROJECT_NAME}_generate_messages_py)
include(cmake/rostests.cmake)

# The fleet layer (python/tread_wear_fleet, docs/fleet.md): its layout's checks, its reductions against hand-computed
# values, and the whole command on a real Dask scheduler with two worker processes, one killed mid-run (needs the
# replay and drive tools).
add_test(NAME fleet_layout COMMAND ${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/fleet/test_fleet_layout.py)
add_test(NAME fleet_reductions COMMAND ${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/fleet/test_fleet_reductions.py)
add_test(NAME fleet_distributed COMMAND ${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/fleet/test_fleet_distributed.py)
set_tests_properties(fleet_distributed PROPERTIES TIMEOUT 180
                     ENVIRONMENT "TREAD_WEAR_BIN=$<TARGET_FILE_DIR:${PROJECT_NAME}_replay>")
# The diagnosis from workshop readings on a tiny fleet: assembled bags, one diagnosis per vehicle and one pooled,
# skipped vehicles, the cache (needs the drive, replay, conceal and diagnose tools).
add_test(NAME fleet_diagnosis COMMAND ${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/test/fleet/test_fleet_diagnosis.py)
set_tests_properties(fleet_diagnosis PROPERTIES TIMEOUT 180
                     ENVIRONMENT "TREAD_WEAR_BIN=$<TARGET_FILE_DIR:${PROJECT_NAME}_replay>")

# Structure checks, part of the test command so that CI and the README run them with everything else:
#  - architecture: the code follows the module map of docs/architecture.md (scripts/check_architecture.py);
#  - catkin_lint: the package files pass catkin_lint (Debian's catkin-lint, installed by scripts/setup.sh) at its
#    default level; --strict fails on any error or warning, -q prints nothing when clean, and any output fails the
#    test too (catkin_lint reports a crash of its own and still exits 0).
add_test(NAME architecture COMMAND ${PYTHON_EXECUTABLE} ${PROJECT_SOURCE_DIR}/scripts/check_architecture.py)
find_program(TREAD_WEAR_CATKIN_LINT catkin_lint)
if(TREAD_WEAR_CATKIN_LINT)
  add_test(NAME catkin_lint COMMAND ${TREAD_WEAR_CATKIN_LINT} --offline -q --strict ${PROJECT_SOURCE_DIR})
  set_tests_properties(catkin_lint PROPERTIES FAIL_REGULAR_EXPRESSION ".")
else()
  message(STATUS "catkin_lint not found: the catkin_lint test is not registered (scripts/setup.sh installs it)")
endif()
