#pragma once
// A small reader of MCAP files, the default storage of ROS 2 bags since Iron (no MCAP reader is packaged in
// Debian). Format reference: the MCAP specification, https://mcap.dev/spec (format version 0x30, "0"):
//   magic 0x89 'M' 'C' 'A' 'P' 0x30 '\r' '\n', then records, then the magic again;
//   a record is opcode (uint8), content length (uint64 little-endian), content;
//   strings are uint32 length + UTF-8 bytes, byte arrays uint32 (uint64 in a Chunk) length + bytes,
//   maps uint32 byte length + entries; integers little-endian.
// Read here: Header (0x01), Footer (0x02), Schema (0x03), Channel (0x04), Message (0x05), Chunk (0x06, with
// compression "", "zstd" or "lz4" (LZ4 frame format), its uncompressed CRC-32 checked when not 0), Statistics
// (0x0B, in the summary) and DataEnd (0x0F). Index, attachment and metadata records are skipped: messages are
// read from the data section, start to end (so files written without a summary are read too); a file must end
// with the closing magic.
//
// Errors are InputError naming the file and what is wrong: not an MCAP file, no closing magic or a record that
// runs past the end of the file (a truncated file), a chunk that does not decompress or whose CRC does not match, an
// unknown compression, a message on a channel never defined.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace seqtopo::recording {

struct McapSchema {
  std::uint16_t id = 0;
  std::string name, encoding;  // e.g. "sensor_msgs/msg/Image", "ros2msg"
  std::vector<std::uint8_t> data;
};

struct McapChannel {
  std::uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;  // e.g. "/camera/image", "cdr"
};

struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0, publish_time = 0;  // [ns]
  std::span<const std::uint8_t> data;
};

class McapReader {
 public:
  // Schemas, channels and the number of messages of each channel: from the summary section when the file has
  // one with a Statistics record (Footer 0x02, Statistics 0x0B), else by reading the whole data section once.
  // Throws InputError on anything malformed.
  explicit McapReader(std::filesystem::path path);

  const std::filesystem::path& path() const { return path_; }
  const std::map<std::uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }
  const std::map<std::uint16_t, std::uint64_t>& message_counts() const { return counts_; }
  std::string profile() const { return profile_; }

  // visit(channel, message) for every message, in log-time order (messages of the same log time in file order,
  // whatever order the file stores them in; the data span lives until visit returns). Messages of the channels
  // in `only` (empty = all) are passed; the others are skipped without copying. Throws InputError when the
  // number of messages of such a channel is not the count of the summary's Statistics record.
  void for_each_message(const std::function<void(const McapChannel&, const McapMessage&)>& visit,
                        const std::vector<std::uint16_t>& only = {}) const;

 private:
  struct Visitor;
  void scan(Visitor& visitor) const;
  bool read_summary();  // channels, schemas and counts from the summary section, when it has Statistics
  std::filesystem::path path_;
  std::string profile_;
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, McapChannel> channels_;
  std::map<std::uint16_t, std::uint64_t> counts_;
};

}  // namespace seqtopo::recording
