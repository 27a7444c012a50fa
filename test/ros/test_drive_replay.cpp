#include <gtest/gtest.h>
TEST(DriveReplay, Placeholder) {}
