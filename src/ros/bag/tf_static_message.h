#pragma once
// Private to ros/bag: the tf2_msgs/TFMessage of /tf_static as a message type of its own (same MD5 sum, type name,
// definition and serialisation), so that the bag tools write and read the IMU mount without tf2 (owned by the
// node's module, docs/architecture.md). A vector of geometry_msgs/TransformStamped.

#include <geometry_msgs/TransformStamped.h>
#include <ros/message_traits.h>
#include <ros/serialization.h>

#include <boost/shared_ptr.hpp>
#include <vector>

namespace tread_wear {

constexpr const char* kTfStaticTopic = "/tf_static";

struct TfStaticMessage {
  std::vector<geometry_msgs::TransformStamped> transforms;
  using Ptr = boost::shared_ptr<TfStaticMessage>;
  using ConstPtr = boost::shared_ptr<const TfStaticMessage>;
};

}  // namespace tread_wear

namespace ros {
namespace message_traits {
template <>
struct MD5Sum<tread_wear::TfStaticMessage> {
  static const char* value() { return "94810edda583a504dfda3829e70d7eec"; }
  static const char* value(const tread_wear::TfStaticMessage&) { return value(); }
};
template <>
struct DataType<tread_wear::TfStaticMessage> {
  static const char* value() { return "tf2_msgs/TFMessage"; }
  static const char* value(const tread_wear::TfStaticMessage&) { return value(); }
};
template <>
struct Definition<tread_wear::TfStaticMessage> {
  static const char* value() {
    return "geometry_msgs/TransformStamped[] transforms\n"
"\n"
"================================================================================\n"
"MSG: geometry_msgs/TransformStamped\n"
"# This expresses a transform from coordinate frame header.frame_id\n"
"# to the coordinate frame child_frame_id\n"
"#\n"
"# This message is mostly used by the \n"
"# <a href=\"http://wiki.ros.org/tf\">tf</a> package. \n"
"# See its documentation for more information.\n"
"\n"
"Header header\n"
"string child_frame_id # the frame id of the child frame\n"
"Transform transform\n"
"\n"
"================================================================================\n"
"MSG: std_msgs/Header\n"
"# Standard metadata for higher-level stamped data types.\n"
"# This is generally used to communicate timestamped data \n"
"# in a particular coordinate frame.\n"
"# \n"
"# sequence ID: consecutively increasing ID \n"
"uint32 seq\n"
"#Two-integer timestamp that is expressed as:\n"
"# * stamp.sec: seconds (stamp_secs) since epoch (in Python the variable is called 'secs')\n"
"# * stamp.nsec: nanoseconds since stamp_secs (in Python the variable is called 'nsecs')\n"
"# time-handling sugar is provided by the client library\n"
"time stamp\n"
"#Frame this data is associated with\n"
"string frame_id\n"
"\n"
"================================================================================\n"
"MSG: geometry_msgs/Transform\n"
"# This represents the transform between two coordinate frames in free space.\n"
"\n"
"Vector3 translation\n"
"Quaternion rotation\n"
"\n"
"================================================================================\n"
"MSG: geometry_msgs/Vector3\n"
"# This represents a vector in free space. \n"
"# It is only meant to represent a direction. Therefore, it does not\n"
"# make sense to apply a translation to it (e.g., when applying a \n"
"# generic rigid transformation to a Vector3, tf2 will only apply the\n"
"# rotation). If you want your data to be translatable too, use the\n"
"# geometry_msgs/Point message instead.\n"
"\n"
"float64 x\n"
"float64 y\n"
"float64 z\n"
"================================================================================\n"
"MSG: geometry_msgs/Quaternion\n"
"# This represents an orientation in free space in quaternion form.\n"
"\n"
"float64 x\n"
"float64 y\n"
"float64 z\n"
"float64 w\n"
;
  }
  static const char* value(const tread_wear::TfStaticMessage&) { return value(); }
};
}  // namespace message_traits
namespace serialization {
template <>
struct Serializer<tread_wear::TfStaticMessage> {
  template <typename Stream, typename T>
  inline static void allInOne(Stream& stream, T m) {
    stream.next(m.transforms);
  }
  ROS_DECLARE_ALLINONE_SERIALIZER
};
}  // namespace serialization
}  // namespace ros
