# Core tests: test/core/test_<name>.cpp -> one gtest binary each, built by default so that build + ctest suffice.
file(GLOB TREAD_WEAR_CORE_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/core/test_*.cpp)
foreach(src ${TREAD_WEAR_CORE_TESTS})
  get_filename_component(name ${src} NAME_WE)
  tread_wear_add_gtest(${name} ${src} tread_wear_core)
  target_compile_definitions(${name} PRIVATE TREAD_WEAR_BINARY_DIR="${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME}")
endforeach()
include(cmake/rostests.cmake OPTIONAL)
