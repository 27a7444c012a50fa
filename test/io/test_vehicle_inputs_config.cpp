// The front end's configuration, one reader for vehicle_inputs_node (the parameter tree) and
// tread_wear_vehicle_inputs (the file): the shipped file gives the documented defaults, a tree with the same keys
// gives the same configuration as the file, and every bad value is named.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "common/temp_file.h"
#include "tread_wear/io/vehicle_inputs_config.h"

namespace tread_wear {
namespace {

const std::string kSource = TREAD_WEAR_SOURCE_DIR;
const std::string kVehicle = kSource + "/config/vehicle_passenger_car.yaml";

ConfigValue text(const std::string& s) {
  ConfigValue v;
  v.type = ConfigValue::Type::kString;
  v.string = s;
  return v;
}
ConfigValue number(double x) {
  ConfigValue v;
  v.type = ConfigValue::Type::kNumber;
  v.number = x;
  return v;
}
ConfigValue boolean(bool b) {
  ConfigValue v;
  v.type = ConfigValue::Type::kBool;
  v.boolean = b;
  return v;
}

ConfigValue document() {
  ConfigValue d;
  d.type = ConfigValue::Type::kMap;
  d.map["vehicle_params_file"] = text(kVehicle);
  return d;
}

std::string errorOf(const ConfigValue& d) {
  VehicleInputsConfig c;
  std::string error;
  EXPECT_FALSE(readVehicleInputsConfig(d, &c, &error));
  return error;
}

TEST(VehicleInputsConfigFile, TheShippedFileGivesTheDocumentedDefaults) {
  const VehicleInputsConfig c = loadVehicleInputsConfigFile(kSource + "/config/vehicle_inputs.yaml", kVehicle);
  EXPECT_EQ(c.publish_rate_hz, 100.0);
  EXPECT_FALSE(c.input_time);
  EXPECT_EQ(c.speed_source, "odom");
  EXPECT_EQ(c.speed_rule, SpeedRule::kPlanarNorm);
  EXPECT_EQ(c.input_delay_s, 0.2);
  EXPECT_TRUE(c.use_wheel_speeds);
  EXPECT_EQ(c.wheel_joints[3], "wheel_rear_right_joint");
  EXPECT_EQ(c.steering_joint, "steering_wheel_joint");
  EXPECT_EQ(c.estimator.steering_ratio, 15.0);
  EXPECT_EQ(c.estimator.wheel_radius_m[2], 0.31);
  EXPECT_EQ(c.estimator.vehicle.mass_kg, 1450.0);
  EXPECT_EQ(c.cog_position_m[2], c.estimator.vehicle.cog_height_m);  // the default: base_link below the CoG
  EXPECT_FALSE(c.cog_position_set);
  EXPECT_EQ(c.vehicle_params_file, kVehicle);
}

TEST(VehicleInputsConfigFile, ATreeWithTheFilesKeysGivesTheSameConfiguration) {
  const TempFile file("publish_rate_hz: 50\ninput_time: true\nspeed_rule: longitudinal\n"
                      "wheel_velocity_signs: [1, -1, 1, -1]\nuse_wheel_speeds: false\n"
                      "estimator:\n  steering_ratio: 16.5\n  wheel_radius_m: [0.3, 0.3, 0.32, 0.32]\n",
                      ".yaml");
  const VehicleInputsConfig from_file = loadVehicleInputsConfigFile(file.path(), kVehicle);
  ConfigValue d = document();
  d.map["publish_rate_hz"] = number(50);
  d.map["input_time"] = boolean(true);
  d.map["speed_rule"] = text("longitudinal");
  ConfigValue signs;
  signs.type = ConfigValue::Type::kList;
  for (double s : {1.0, -1.0, 1.0, -1.0}) signs.list.push_back(number(s));
  d.map["wheel_velocity_signs"] = signs;
  d.map["use_wheel_speeds"] = boolean(false);
  ConfigValue estimator, radii;
  estimator.type = ConfigValue::Type::kMap;
  radii.type = ConfigValue::Type::kList;
  for (double r : {0.3, 0.3, 0.32, 0.32}) radii.list.push_back(number(r));
  estimator.map["steering_ratio"] = number(16.5);
  estimator.map["wheel_radius_m"] = radii;
  d.map["estimator"] = estimator;
  VehicleInputsConfig from_tree;
  std::string error;
  ASSERT_TRUE(readVehicleInputsConfig(d, &from_tree, &error)) << error;
  EXPECT_EQ(from_file.describe(), from_tree.describe());
  EXPECT_EQ(from_tree.publish_rate_hz, 50.0);
  EXPECT_TRUE(from_tree.input_time);
  EXPECT_EQ(from_tree.speed_rule, SpeedRule::kLongitudinal);
  EXPECT_EQ(from_tree.wheel_velocity_signs[1], -1.0);
  EXPECT_FALSE(from_tree.use_wheel_speeds);
  EXPECT_EQ(from_tree.estimator.wheel_radius_m[3], 0.32);
  EXPECT_EQ(from_file.wheel_velocity_signs, from_tree.wheel_velocity_signs);
  EXPECT_EQ(from_file.use_wheel_speeds, from_tree.use_wheel_speeds);
}

TEST(VehicleInputsConfigFile, EveryBadValueIsNamed) {
  ConfigValue d = document();
  d.map.erase("vehicle_params_file");
  EXPECT_EQ(errorOf(d), "vehicle_params_file: required (config/vehicle_*.yaml)");
  d = document();
  d.map["speed_rule"] = text("sideways");
  EXPECT_EQ(errorOf(d), "speed_rule = 'sideways': must be planar_norm or longitudinal");
  d = document();
  d.map["speed_rule"] = number(1);
  EXPECT_EQ(errorOf(d), "speed_rule: must be a string");
  d = document();
  d.map["input_time"] = text("sometimes");
  EXPECT_EQ(errorOf(d), "input_time: must be true or false");
  d = document();
  d.map["publish_rate_hz"] = number(0);
  EXPECT_EQ(errorOf(d), "publish_rate_hz = 0: must be in (0, 1000] [Hz]");
  d = document();
  d.map["input_delay_s"] = number(2);
  EXPECT_EQ(errorOf(d), "input_delay_s = 2: must be in [0, 1] [s]");
  d = document();
  ConfigValue three;
  three.type = ConfigValue::Type::kList;
  for (int i = 0; i < 3; ++i) three.list.push_back(number(0.3));
  ConfigValue estimator;
  estimator.type = ConfigValue::Type::kMap;
  estimator.map["wheel_radius_m"] = three;
  d.map["estimator"] = estimator;
  EXPECT_EQ(errorOf(d), "estimator/wheel_radius_m: must be a list of 4 numbers");
  d = document();
  d.map["vehicle_params_file"] = text("/no/such/vehicle.yaml");
  EXPECT_NE(errorOf(d).find("vehicle_params_file: "), std::string::npos);
  EXPECT_THROW(loadVehicleInputsConfigFile("/no/such/inputs.yaml", kVehicle), std::runtime_error);
}

}  // namespace
}  // namespace tread_wear
