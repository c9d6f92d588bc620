// The record structure of a ROS 1 bag (format 2.0), checked before the bag
// library reads it: that library trusts every length and offset in the file,
// and a damaged one made it read past its buffers (a crash) or ask for
// gigabytes (an abort), with no message naming the file.
#include "rosbag_check.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "lom/error.hpp"

#ifdef LOM_WITH_ROSBAG
#include <bzlib.h>
#include <roslz4/lz4s.h>
#endif

namespace lom::import_detail {

namespace {

namespace fs = std::filesystem;

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr std::uint64_t kMagicBytes = sizeof(kMagic) - 1;
constexpr std::uint64_t kVersionAt = 9;  // "#ROSBAG V" then the version
// Record operations of format 2.0.
constexpr std::uint8_t kMessageData = 0x02, kBagHeader = 0x03, kIndexData = 0x04, kChunk = 0x05,
                       kChunkInfo = 0x06, kConnection = 0x07;
// A record header is a few named fields: far below this.
constexpr std::uint32_t kMaxHeaderBytes = 1u << 20;
// A compressed chunk's stated size, at most this many times its data (lz4
// packs at most 255:1; bz2 more on uniform data): the library allocates it.
constexpr std::uint64_t kMaxCompression = 4096;

struct Fields {
  std::map<std::string, std::string> values;
  [[nodiscard]] std::optional<std::uint64_t> number(const std::string& name, size_t bytes) const {
    const auto it = values.find(name);
    if (it == values.end() || it->second.size() != bytes) return std::nullopt;
    std::uint64_t value = 0;
    for (size_t i = 0; i < bytes; ++i)
      value |= static_cast<std::uint64_t>(static_cast<unsigned char>(it->second[i])) << (8 * i);
    return value;
  }
};

// Where a walker reads: the file, or a chunk decompressed in memory.
struct Source {
  std::ifstream* file = nullptr;
  const std::vector<char>* memory = nullptr;
  std::uint64_t size = 0;
  std::string where;  // follows the byte offsets of messages
};

// The data of a compressed chunk, decompressed as the bag library does it;
// empty when the compression is one it does not know (it says so itself).
// Throws std::runtime_error when the data does not decompress to `size` bytes.
std::optional<std::vector<char>> decompressChunk(const std::string& compression,
                                                 std::vector<char>& packed, std::uint64_t size) {
#ifdef LOM_WITH_ROSBAG
  if (compression != "bz2" && compression != "lz4") return std::nullopt;
  if (size > 0xffffffffu || packed.size() > 0xffffffffu)
    throw std::runtime_error("a chunk over 4 GiB");
  std::vector<char> unpacked(size + 1);  // one more: data beyond `size` shows
  auto out = static_cast<unsigned int>(unpacked.size());
  const auto in = static_cast<unsigned int>(packed.size());
  const bool ok =
      compression == "bz2"
          ? BZ2_bzBuffToBuffDecompress(unpacked.data(), &out, packed.data(), in, 0, 0) == BZ_OK
          : roslz4_buffToBuffDecompress(packed.data(), in, unpacked.data(), &out) == ROSLZ4_OK;
  if (!ok) throw std::runtime_error("data that does not decompress as " + compression);
  if (out != size)
    throw std::runtime_error("data that decompresses to " + std::to_string(out) +
                             (out > size ? " or more" : "") + " bytes, not the " +
                             std::to_string(size) + " its header states");
  unpacked.resize(size);
  return unpacked;
#else
  (void)compression, (void)packed, (void)size;
  return std::nullopt;
#endif
}

class Walker {
 public:
  Walker(const std::string& file, Source source, const BagCheckProgress* keep_going = nullptr)
      : file_(file), source_(std::move(source)), keep_going_(keep_going) {}

  [[noreturn]] void fail(std::uint64_t at, const std::string& what) const {
    throw Error(file_, "bag", "a readable ROS 1 bag (format 2.0)",
                what + " at byte " + std::to_string(at) + source_.where +
                    " (the file is damaged or cut short; `rosbag reindex` or `rosbag check` on a "
                    "copy may tell more)");
  }

  std::uint32_t u32(std::uint64_t at) {
    unsigned char bytes[4];
    read(at, bytes, 4);
    return static_cast<std::uint32_t>(bytes[0]) | (static_cast<std::uint32_t>(bytes[1]) << 8) |
           (static_cast<std::uint32_t>(bytes[2]) << 16) |
           (static_cast<std::uint32_t>(bytes[3]) << 24);
  }

  void read(std::uint64_t at, void* into, std::uint64_t count) {
    if (at + count > source_.size) fail(at, "a record that runs past the end of the file");
    if (source_.memory) {
      if (count > 0) std::memcpy(into, source_.memory->data() + at, count);
      return;
    }
    source_.file->seekg(static_cast<std::streamoff>(at));
    source_.file->read(static_cast<char*>(into), static_cast<std::streamsize>(count));
    if (!*source_.file) fail(at, "bytes that cannot be read");
  }

  // The records of a chunk's data, [from, from + bytes): connections and
  // messages only; adds each record's offset from `from` to `starts`.
  void chunkRecords(std::uint64_t from, std::uint64_t bytes, std::set<std::uint32_t>& starts) {
    Fields inner;
    std::uint64_t inner_data = 0;
    std::uint32_t inner_bytes = 0;
    for (std::uint64_t in = from; in < from + bytes;) {
      starts.insert(static_cast<std::uint32_t>(in - from));
      const std::uint64_t after = record(in, from + bytes, inner, inner_data, inner_bytes);
      const std::uint8_t inner_op = op(inner, in);
      if (inner_op != kMessageData && inner_op != kConnection)
        fail(in, "a record that does not belong in a chunk");
      in = after;
    }
  }

  // One record from `at` (within [at, end)): its header fields and where its
  // data lies; returns the offset after it.
  std::uint64_t record(std::uint64_t at, std::uint64_t end, Fields& fields, std::uint64_t& data_at,
                       std::uint32_t& data_bytes) {
    if (at + 4 > end) fail(at, "a record header length cut short");
    const std::uint32_t header_bytes = u32(at);
    if (header_bytes > kMaxHeaderBytes || at + 4 + header_bytes + 4 > end)
      fail(at, "a record header of " + std::to_string(header_bytes) +
                   " bytes that does not fit in what follows it");
    std::string header(header_bytes, '\0');
    read(at + 4, header.data(), header_bytes);
    fields.values.clear();
    for (size_t pos = 0; pos < header.size();) {
      if (pos + 4 > header.size()) fail(at, "a record header field cut short");
      std::uint32_t length = 0;
      for (int b = 0; b < 4; ++b)
        length |= static_cast<std::uint32_t>(static_cast<unsigned char>(header[pos + b]))
                  << (8 * b);
      pos += 4;
      if (length > header.size() - pos) fail(at, "a record header field longer than its header");
      const std::string field = header.substr(pos, length);
      const size_t equals = field.find('=');
      if (equals == std::string::npos) fail(at, "a record header field without '='");
      fields.values[field.substr(0, equals)] = field.substr(equals + 1);
      pos += length;
    }
    data_bytes = u32(at + 4 + header_bytes);
    data_at = at + 8 + header_bytes;
    if (data_at + data_bytes > end)
      fail(at, "record data of " + std::to_string(data_bytes) +
                   " bytes that runs past the end of its container");
    return data_at + data_bytes;
  }

  std::uint8_t op(const Fields& fields, std::uint64_t at) const {
    const auto value = fields.number("op", 1);
    if (!value) fail(at, "a record without its operation field");
    return static_cast<std::uint8_t>(*value);
  }

  // False when keep_going said to stop.
  bool walk() {
    // The bag library calls any file it cannot read a truncated bag: one
    // that is no bag at all is said to be none, not sent to `rosbag reindex`.
    char magic[kMagicBytes];
    const std::uint64_t start = std::min<std::uint64_t>(source_.size, kMagicBytes);
    read(0, magic, start);
    if (std::memcmp(magic, kMagic, start) != 0) {
      if (std::memcmp(magic, kMagic, std::min<std::uint64_t>(start, kVersionAt)) == 0 &&
          start > kVersionAt)
        return true;  // another version of the format: the library's to judge
      throw Error(file_, "bag", "a readable ROS 1 bag (format 2.0)",
                  "a file that is not a ROS bag (it does not start with #ROSBAG V2.0)");
    }
    if (start < kMagicBytes) fail(start, "the file ending inside its first line, #ROSBAG V2.0");
    Fields fields;
    std::uint64_t data_at = 0;
    std::uint32_t data_bytes = 0;
    struct Chunk {
      std::uint64_t size = 0;                 // uncompressed
      std::set<std::uint32_t> record_starts;  // within its data, once walked
      bool walked = false;                    // false: a compression the library judges
    };
    std::map<std::uint64_t, Chunk> chunks;  // by file offset
    std::optional<std::uint64_t> last_chunk;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> chunk_infos;  // record offset, chunk_pos
    for (std::uint64_t at = kMagicBytes; at < source_.size;) {
      if (keep_going_ && *keep_going_ && !(*keep_going_)(at, source_.size)) return false;
      const std::uint64_t next = record(at, source_.size, fields, data_at, data_bytes);
      const std::uint8_t operation = op(fields, at);
      if (operation == kBagHeader) {
        // (An index position past the end is a bag not closed when recorded:
        // the bag library says so, unindexed, in its own words.)
        if (!fields.number("index_pos", 8)) fail(at, "a bag header without its index position");
      } else if (operation == kChunk) {
        Chunk chunk;
        const auto compression = fields.values.find("compression");
        const auto stated = fields.number("size", 4);
        if (compression == fields.values.end() || !stated)
          fail(at, "a chunk without its compression or size");
        chunk.size = *stated;
        const bool compressed = compression->second != "none";
        if (compressed && chunk.size > kMaxCompression * data_bytes + (1u << 20))
          fail(at, "a compressed chunk of " + std::to_string(data_bytes) + " bytes said to hold " +
                       std::to_string(chunk.size));
        if (!compressed) {
          if (chunk.size != data_bytes)
            fail(at, "an uncompressed chunk whose size differs from its data");
          chunkRecords(data_at, data_bytes, chunk.record_starts);
          chunk.walked = true;
        } else {
          // Decompressed here too (a second time, as the library reads it):
          // the records inside are as trusted by the library as those outside.
          std::vector<char> packed(data_bytes);
          read(data_at, packed.data(), data_bytes);
          std::optional<std::vector<char>> unpacked;
          try {
            unpacked = decompressChunk(compression->second, packed, chunk.size);
          } catch (const std::runtime_error& e) {
            fail(at, "a " + compression->second + " chunk with " + e.what());
          }
          if (unpacked) {
            Walker inner(file_, Source{nullptr, &*unpacked, unpacked->size(),
                                       " of the chunk decompressed from the record at byte " +
                                           std::to_string(at)});
            inner.chunkRecords(0, unpacked->size(), chunk.record_starts);
            chunk.walked = true;
          }
        }
        chunks[at] = std::move(chunk);
        last_chunk = at;
      } else if (operation == kIndexData) {
        const auto count = fields.number("count", 4);
        if (!count || !fields.number("ver", 4) || !fields.number("conn", 4))
          fail(at, "an index record without its version, connection or count");
        if (static_cast<std::uint64_t>(*count) * 12 != data_bytes)
          fail(at, "an index record whose entries do not fill its data");
        if (!last_chunk) fail(at, "an index record before any chunk");
        const Chunk& chunk = chunks[*last_chunk];
        for (std::uint64_t i = 0; i < *count; ++i) {
          const std::uint32_t offset = u32(data_at + i * 12 + 8);
          const bool inside =
              chunk.walked ? chunk.record_starts.count(offset) > 0 : offset < chunk.size;
          if (!inside) fail(at, "an index entry pointing outside the records of its chunk");
        }
      } else if (operation == kChunkInfo) {
        const auto count = fields.number("count", 4);
        const auto chunk_pos = fields.number("chunk_pos", 8);
        if (!count || !chunk_pos)
          fail(at, "a chunk info record without its chunk position or count");
        if (static_cast<std::uint64_t>(*count) * 8 != data_bytes)
          fail(at, "a chunk info record whose entries do not fill its data");
        chunk_infos.emplace_back(at, *chunk_pos);
      } else if (operation == kConnection) {
        if (!fields.number("conn", 4) || fields.values.count("topic") == 0)
          fail(at, "a connection record without its number or topic");
      } else if (operation != kMessageData) {
        fail(at, "a record of unknown operation " + std::to_string(operation));
      }
      at = next;
    }
    for (const auto& [at, chunk_pos] : chunk_infos)
      if (chunks.count(chunk_pos) == 0) fail(at, "a chunk info record pointing at no chunk");
    return true;
  }

 private:
  const std::string& file_;
  Source source_;
  const BagCheckProgress* keep_going_;
};

// The fields of one serialised message, read in order; stops at the first
// length that does not fit.
class MessageWalker {
 public:
  MessageWalker(const std::uint8_t* bytes, size_t size) : bytes_(bytes), size_(size) {}

  [[nodiscard]] const std::optional<MessageLengthProblem>& problem() const { return problem_; }

  bool fixed(const std::string& field, size_t bytes) {
    if (problem_) return false;
    if (bytes > size_ - at_) {
      problem_ = MessageLengthProblem{
          field, std::to_string(bytes) + " bytes",
          "the message ends " + std::to_string(size_ - at_) + " bytes into it"};
      return false;
    }
    at_ += bytes;
    return true;
  }

  // A string or array: a 4-byte length, then that many elements of
  // `element` bytes (at least that many when not `fixed_size`); the
  // length, or nothing when it does not fit.
  std::optional<std::uint32_t> array(const std::string& field, size_t element, const char* what,
                                     bool fixed_size = true) {
    if (problem_) return std::nullopt;
    if (size_ - at_ < 4) {
      fixed(field + " length", 4);
      return std::nullopt;
    }
    std::uint32_t length = 0;
    for (int b = 0; b < 4; ++b) length |= static_cast<std::uint32_t>(bytes_[at_ + b]) << (8 * b);
    at_ += 4;
    const size_t left = size_ - at_;
    if (length > left / element) {
      problem_ = MessageLengthProblem{
          field, "a length that fits in the " + std::to_string(left) + " bytes left in the message",
          std::to_string(length) + " " + what +
              (element > 1 && fixed_size
                   ? " (" + std::to_string(static_cast<std::uint64_t>(length) * element) + " bytes)"
                   : std::string())};
      return std::nullopt;
    }
    return length;
  }

  bool bytes(const std::string& field, size_t element, const char* what) {
    const auto length = array(field, element, what);
    if (!length) return false;
    at_ += static_cast<size_t>(*length) * element;
    return true;
  }

  bool text(const std::string& field) { return bytes(field, 1, "characters"); }

  bool header(const std::string& prefix) {
    return fixed(prefix + "header.seq", 4) && fixed(prefix + "header.stamp", 8) &&
           text(prefix + "header.frame_id");
  }

 private:
  const std::uint8_t* bytes_;
  size_t size_;
  size_t at_ = 0;
  std::optional<MessageLengthProblem> problem_;
};

}  // namespace

std::optional<MessageLengthProblem> messageLengthProblem(const std::string& type,
                                                         const std::uint8_t* bytes, size_t size) {
  MessageWalker m(bytes, size);
  if (type == "sensor_msgs/Image") {
    (void)(m.header("") && m.fixed("height", 4) && m.fixed("width", 4) && m.text("encoding") &&
           m.fixed("is_bigendian", 1) && m.fixed("step", 4) && m.bytes("data", 1, "bytes"));
  } else if (type == "sensor_msgs/CompressedImage") {
    (void)(m.header("") && m.text("format") && m.bytes("data", 1, "bytes"));
  } else if (type == "sensor_msgs/CameraInfo") {
    (void)(m.header("") && m.fixed("height", 4) && m.fixed("width", 4) &&
           m.text("distortion_model") && m.bytes("D", 8, "float64 values") && m.fixed("K", 72) &&
           m.fixed("R", 72) && m.fixed("P", 96) && m.fixed("binning", 8) && m.fixed("roi", 17));
  } else if (type == "tf2_msgs/TFMessage" || type == "tf/tfMessage") {
    // A transform takes at least 76 bytes: a header with an empty frame,
    // an empty child frame, 7 float64.
    const auto count = m.array("transforms", 76, "transforms", false);
    for (std::uint32_t i = 0; count && i < *count; ++i) {
      const std::string at = "transforms[" + std::to_string(i) + "].";
      if (!(m.header(at) && m.text(at + "child_frame_id") && m.fixed(at + "transform", 56))) break;
    }
  }
  return m.problem();
}

bool checkBagStructure(const std::string& file, const BagCheckProgress& keep_going) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    // A folder of bags (e.g. a recording split with --split) names them.
    std::string bags;
    size_t count = 0;
    for (const auto& entry : fs::directory_iterator(file, ec)) {
      std::string ext = entry.path().extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (ext != ".bag" || ++count > 3) continue;
      bags += (bags.empty() ? "" : ", ") + entry.path().filename().string();
    }
    if (count > 3) bags += ", ...";
    throw Error(
        file, "bag", "a .bag file",
        "a folder" + (bags.empty() ? std::string() : " (give one of its bags: " + bags + ")"));
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) return true;  // the bag library names what is wrong with opening it
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  if (end < 0) return true;
  if (end == 0)
    throw Error(file, "bag", "a readable ROS 1 bag (format 2.0)", "a file that is empty");
  Walker walker(file, Source{&in, nullptr, static_cast<std::uint64_t>(end), ""}, &keep_going);
  return walker.walk();
}

}  // namespace lom::import_detail
