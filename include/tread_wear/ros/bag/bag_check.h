#pragma once
/// @file bag_check.h
/// The safety check every bag goes through before rosbag reads it, and BagError, the error of the bag functions
/// of ros/bag.

#include <stdexcept>
#include <string>

namespace rosbag {
class Bag;
}  // namespace rosbag

namespace tread_wear {

/// A bag that cannot be replayed: missing or unreadable file, corrupt or truncated data, missing topics,
/// wrong message types. what() names the file and the problem.
class BagError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Checks the records of a rosbag 2.0 file before rosbag reads it, since rosbag and ros::Header::parse read
/// lengths from the file without bounds checks (a corrupt one makes them read past their buffers, or crash): every
/// record and header field must lie within the file, every record of every chunk within its chunk (bz2 and lz4
/// chunks are decompressed first, to exactly their size field, at most 1 GiB), and every index entry must point at
/// a record of its chunk that leads to a message. Chunks of another compression are left to rosbag, as are other
/// bag versions. Reads the file once, a record at a time (memory: one chunk, and its decompressed data).
/// @throw BagError naming the file, the problem and its byte offset
void checkBagRecords(const std::string& path);

/// Opens `bag` for writing at `path` (the one place the tools create a bag). @throw BagError naming the file
void openBagForWriting(rosbag::Bag* bag, const std::string& path);

}  // namespace tread_wear
