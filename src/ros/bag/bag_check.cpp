#include "tread_wear/ros/bag/bag_check.h"

#include <bzlib.h>
#include <rosbag/bag.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

namespace tread_wear {

namespace {

// rosbag 2.0 records: uint32 header length, header fields (each uint32 length + "name=value"), uint32 data
// length, data; all integers little-endian. The "op" field tells the record type.
constexpr char kOpMessageDefinition = 0x01, kOpMessageData = 0x02, kOpIndexData = 0x04, kOpChunk = 0x05,
               kOpConnection = 0x07;
constexpr std::size_t kVersionLineBytes = 13;  // "#ROSBAG V2.0\n"

std::uint64_t littleEndian(const char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}

/// A record found in `bytes[0, size)` at `pos`: the header fields this check needs, and where its data lie.
struct Record {
  char op = 0;
  std::string_view compression, size;  ///< chunk header fields (views into the bytes)
  std::uint64_t data_pos = 0, data_len = 0, end = 0;
};

/// Parses the record at `pos` of a stretch of `size` bytes whose first `available` are in `bytes` (at least its
/// header and data length, or to the end); an empty string, or what runs past the end or is malformed.
std::string parseRecord(const char* bytes, std::uint64_t available, std::uint64_t size, std::uint64_t pos,
                        Record* r) {
  if (available - pos < 4) return "record header length past the end";
  const std::uint64_t header_len = littleEndian(bytes + pos, 4);
  if (header_len > available - pos - 4) return "record header of " + std::to_string(header_len) + " bytes past the end";
  std::uint64_t at = pos + 4;
  const std::uint64_t header_end = at + header_len;
  *r = Record();
  while (at < header_end) {
    if (header_end - at < 4) return "header field length past the header";
    const std::uint64_t field_len = littleEndian(bytes + at, 4);
    at += 4;
    if (field_len > header_end - at) return "header field of " + std::to_string(field_len) + " bytes past the header";
    const std::string_view field(bytes + at, field_len);
    const auto eq = field.find('=');
    if (eq == std::string_view::npos) return "header field without '='";
    const std::string_view name = field.substr(0, eq), value = field.substr(eq + 1);
    if (name == "op" && value.size() == 1) r->op = value[0];
    if (name == "compression") r->compression = value;
    if (name == "size") r->size = value;
    at += field_len;
  }
  if (available - header_end < 4) return "record data length past the end";
  r->data_len = littleEndian(bytes + header_end, 4);
  r->data_pos = header_end + 4;
  if (r->data_len > size - r->data_pos) return "record data of " + std::to_string(r->data_len) + " bytes past the end";
  r->end = r->data_pos + r->data_len;
  return "";
}

/// Largest decompressed chunk the check accepts [bytes]. rosbag allocates a compressed chunk's size field before it
/// decompresses, so a corrupt one must not ask for gigabytes (rosbag's chunks hold about 768 KB by default; a chunk
/// exceeds that only by its last message). An uncompressed chunk's size is its data length, within the file.
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;

/// Decompresses a bz2 or lz4 chunk (the codecs rosbag writes) into `out`, sized to the chunk's size field; false
/// when the data do not decompress to exactly that many bytes.
bool decompressChunk(std::string_view compression, std::vector<char>* in, std::vector<char>* out) {
  unsigned int out_len = static_cast<unsigned int>(out->size());
  const unsigned int in_len = static_cast<unsigned int>(in->size());
  const bool ok = compression == "bz2"
                      ? BZ2_bzBuffToBuffDecompress(out->data(), &out_len, in->data(), in_len, 0, 0) == BZ_OK
                      : roslz4_buffToBuffDecompress(in->data(), in_len, out->data(), &out_len) == ROSLZ4_OK;
  return ok && out_len == out->size();
}

}  // namespace

void checkBagRecords(const std::string& path) {
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(path, ec);  // an error for a directory too
  std::ifstream file(path, std::ios::binary);
  // Reads [offset, offset + count) of the file (count <= size - offset) into `out`.
  auto readAt = [&](std::uint64_t offset, std::uint64_t count, std::vector<char>* out) {
    out->resize(count);
    if (!file.seekg(static_cast<std::streamoff>(offset)) || !file.read(out->data(), static_cast<std::streamsize>(count)))
      throw BagError(path + ": cannot read the bag at byte " + std::to_string(offset));
  };
  if (ec || !file) throw BagError(path + ": cannot open the bag (missing or unreadable file)");
  std::vector<char> head, data;  // a record's header, and the data of a chunk or index record
  std::vector<char> unpacked;    // a compressed chunk's data, decompressed
  if (size >= kVersionLineBytes) readAt(0, kVersionLineBytes, &head);
  if (size < kVersionLineBytes || std::string(head.data(), kVersionLineBytes) != "#ROSBAG V2.0\n")
    return;  // not a 2.0 bag: rosbag reads older versions and names what it cannot read
  auto corrupt = [&](const std::string& what, std::uint64_t at) {
    return BagError(path + ": bag data unreadable (corrupt): " + what + " at byte " + std::to_string(at));
  };
  // Record starts of the last checked chunk (relative to its data, decompressed if compressed; ascending) with
  // their ops.
  std::vector<std::pair<std::uint64_t, char>> chunk_records;
  bool chunk_checked = false;
  Record r;
  // One record at a time: its header is read first, then the data of a chunk or index record only, so memory
  // stays at one chunk whatever the size of the bag.
  for (std::uint64_t pos = kVersionLineBytes; pos < size; pos += r.end) {
    readAt(pos, std::min<std::uint64_t>(size - pos, 4), &head);
    if (head.size() == 4)  // then up to the data length: uint32 header length, header, uint32 data length
      readAt(pos, std::min(size - pos, 8 + littleEndian(head.data(), 4)), &head);
    const std::string error = parseRecord(head.data(), head.size(), size - pos, 0, &r);
    if (!error.empty())
      throw BagError(path + ": not a readable bag (corrupt or truncated: " + error + " of the file at byte " +
                     std::to_string(pos) + "; `rosbag reindex` may recover a truncated one)");
    const std::uint64_t data_at = pos + r.data_pos;
    if (r.op == kOpChunk) {
      chunk_records.clear();
      const bool compressed = r.compression == "bz2" || r.compression == "lz4";
      chunk_checked = compressed || r.compression == "none";
      if (!chunk_checked) continue;  // rosbag names a compression it does not know
      // The size field: the data length of an uncompressed chunk, the decompressed length of a compressed one. A
      // missing field equals no uint32 data length and exceeds the cap.
      const std::uint64_t chunk_len =
          r.size.size() == 4 ? littleEndian(r.size.data(), 4) : std::numeric_limits<std::uint64_t>::max();
      if (!compressed && chunk_len != r.data_len)
        throw corrupt("uncompressed chunk whose size field differs from its data length", pos);
      if (compressed && chunk_len > kMaxChunkBytes)
        throw corrupt("chunk whose size field is missing or above " + std::to_string(kMaxChunkBytes) + " bytes", pos);
      readAt(data_at, r.data_len, &data);
      if (compressed) {
        unpacked.resize(chunk_len);
        if (!decompressChunk(r.compression, &data, &unpacked))
          throw corrupt(std::string(r.compression) + " chunk that does not decompress to its size field (" +
                            std::to_string(chunk_len) + " bytes)",
                        pos);
      }
      const std::vector<char>& chunk = compressed ? unpacked : data;
      Record inner;
      for (std::uint64_t at = 0; at < chunk_len; at = inner.end) {
        const std::string inner_error = parseRecord(chunk.data(), chunk_len, chunk_len, at, &inner);
        if (!inner_error.empty() && compressed)
          throw corrupt(inner_error + " of its decompressed chunk (at its byte " + std::to_string(at) + ")", pos);
        if (!inner_error.empty()) throw corrupt(inner_error + " of its chunk", data_at + at);
        chunk_records.emplace_back(at, inner.op);
      }
    } else if (r.op == kOpIndexData && chunk_checked) {
      if (r.data_len % 12 != 0) throw corrupt("index data not a whole number of entries", pos);
      readAt(data_at, r.data_len, &data);
      for (std::uint64_t e = 0; e < r.data_len; e += 12) {
        const std::uint64_t offset = littleEndian(data.data() + e + 8, 4);
        // rosbag reads from the entry's record on, past connection and definition records, to a message.
        auto it = std::lower_bound(chunk_records.begin(), chunk_records.end(), std::make_pair(offset, char{0}));
        if (it != chunk_records.end() && it->first != offset) it = chunk_records.end();
        while (it != chunk_records.end() && (it->second == kOpConnection || it->second == kOpMessageDefinition)) ++it;
        if (it == chunk_records.end() || it->second != kOpMessageData)
          throw corrupt("index entry pointing at no message of its chunk (offset " + std::to_string(offset) + ")",
                        data_at + e);
      }
    }
  }
}

void openBagForWriting(rosbag::Bag* bag, const std::string& path) {
  try {
    bag->open(path, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": cannot write the bag: " + e.what());
  }
}

}  // namespace tread_wear
