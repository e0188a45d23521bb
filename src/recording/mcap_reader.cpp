#include "seqtopo/recording/mcap_reader.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "seqtopo/core/input_error.hpp"

namespace seqtopo::recording {

namespace fs = std::filesystem;

namespace {

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
enum Opcode : std::uint8_t {
  header = 0x01,
  footer = 0x02,
  schema = 0x03,
  channel = 0x04,
  message = 0x05,
  chunk = 0x06,
  statistics = 0x0B,
  data_end = 0x0F,
};

// Little-endian fields of one record's content, bounds-checked.
class Fields {
 public:
  Fields(std::span<const std::uint8_t> b, const std::string& what) : b_(b), what_(what) {}
  template <typename T>
  T num() {
    const auto s = take(sizeof(T));
    T v;
    std::memcpy(&v, s.data(), sizeof(T));  // the host is little-endian (x86-64, arm64)
    return v;
  }
  std::string str() {
    const auto n = num<std::uint32_t>();
    const auto s = take(n);
    return std::string(reinterpret_cast<const char*>(s.data()), s.size());
  }
  std::span<const std::uint8_t> bytes32() { return take(num<std::uint32_t>()); }
  std::span<const std::uint8_t> bytes64() {
    const auto n = num<std::uint64_t>();
    return take(n);
  }
  std::span<const std::uint8_t> rest() { return take(b_.size() - at_); }

 private:
  std::span<const std::uint8_t> take(std::uint64_t n) {
    if (n > b_.size() - at_) {
      throw std::invalid_argument(what_ + ": a field of " + std::to_string(n) + " bytes runs past the record's end");
    }
    const auto s = b_.subspan(at_, static_cast<std::size_t>(n));
    at_ += static_cast<std::size_t>(n);
    return s;
  }
  std::span<const std::uint8_t> b_;
  std::size_t at_ = 0;
  std::string what_;
};

std::vector<std::uint8_t> decompress(const std::string& compression, std::span<const std::uint8_t> in,
                                     std::uint64_t size, const std::string& where) {
  if (size > (std::uint64_t{1} << 36U)) throw std::invalid_argument(where + ": uncompressed size is implausible");
  std::vector<std::uint8_t> out(static_cast<std::size_t>(size));
  if (compression == "zstd") {
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
    if (ZSTD_isError(n)) {
      throw std::invalid_argument(where + ": zstd chunk does not decompress (" + ZSTD_getErrorName(n) + ")");
    }
    if (n != out.size()) {
      throw std::invalid_argument(where + ": zstd chunk decompresses to " + std::to_string(n) + " bytes, expected " +
                                  std::to_string(out.size()));
    }
    return out;
  }
  if (compression == "lz4") {
    LZ4F_dctx* ctx = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) {
      throw std::runtime_error("cannot create an LZ4 decompression context");
    }
    std::size_t produced = 0, consumed = 0;
    std::size_t status = 1;
    while (consumed < in.size() && status != 0) {
      std::size_t dst = out.size() - produced, src = in.size() - consumed;
      status = LZ4F_decompress(ctx, out.data() + produced, &dst, in.data() + consumed, &src, nullptr);
      if (LZ4F_isError(status)) {
        const std::string reason = LZ4F_getErrorName(status);
        LZ4F_freeDecompressionContext(ctx);
        throw std::invalid_argument(where + ": lz4 chunk does not decompress (" + reason + ")");
      }
      produced += dst;
      consumed += src;
      if (dst == 0 && src == 0) break;
    }
    LZ4F_freeDecompressionContext(ctx);
    if (status != 0 || produced != out.size()) {
      throw std::invalid_argument(where + ": lz4 chunk ends early (" + std::to_string(produced) + " of " +
                                  std::to_string(out.size()) + " bytes)");
    }
    return out;
  }
  if (compression.empty()) {
    if (in.size() != size) throw std::invalid_argument(where + ": uncompressed chunk size does not match its records");
    return {in.begin(), in.end()};
  }
  throw std::invalid_argument(where + ": unknown chunk compression '" + compression + "' (zstd, lz4 or none)");
}

constexpr std::size_t kNotInChunk = static_cast<std::size_t>(-1);

// The records of a Chunk record's content, decompressed and checked against the chunk's CRC-32.
std::vector<std::uint8_t> unpack_chunk(std::span<const std::uint8_t> content, const std::string& where) {
  Fields f(content, where);
  (void)f.num<std::uint64_t>();  // message_start_time
  (void)f.num<std::uint64_t>();  // message_end_time
  const auto size = f.num<std::uint64_t>();
  const auto crc = f.num<std::uint32_t>();
  const std::string compression = f.str();
  const auto packed = f.bytes64();
  std::vector<std::uint8_t> inner = decompress(compression, packed, size, where);
  // zlib's crc32 is MCAP's CRC-32 (ISO-HDLC); 0 means the writer left the chunk unchecked.
  if (crc != 0 && ::crc32(0L, inner.data(), static_cast<uInt>(inner.size())) != crc) {
    throw std::invalid_argument(where + ": CRC-32 of the decompressed records does not match (corrupt chunk)");
  }
  return inner;
}

McapMessage parse_message(std::span<const std::uint8_t> content, const std::string& where) {
  Fields f(content, where);
  McapMessage m;
  m.channel_id = f.num<std::uint16_t>();
  m.sequence = f.num<std::uint32_t>();
  m.log_time = f.num<std::uint64_t>();
  m.publish_time = f.num<std::uint64_t>();
  m.data = f.rest();
  return m;
}

}  // namespace

struct McapReader::Visitor {
  std::function<void(const McapSchema&)> on_schema;
  std::function<void(const McapChannel&)> on_channel;
  // message, the offset of its record (or of its chunk), its offset inside the chunk (or kNotInChunk)
  std::function<void(const McapMessage&, std::size_t, std::size_t)> on_message;
  std::function<bool(std::uint16_t)> wants;  // whether a channel's messages are parsed
  std::function<void(const std::string&)> on_header;
  bool stop_after_header = false;
};

void McapReader::scan(Visitor& v) const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) throw InputError(path_.string(), "cannot open file");
  in.seekg(0, std::ios::end);
  const auto file_size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  std::uint8_t magic[8] = {};
  in.read(reinterpret_cast<char*>(magic), 8);
  if (!in || std::memcmp(magic, kMagic, 8) != 0) {
    throw InputError(path_.string(), "not an MCAP file (no MCAP magic at its start)");
  }
  // A complete file ends with the magic too; a writer that stopped early, or a cut copy, does not.
  std::uint8_t tail[8] = {};
  if (file_size >= 16) {
    in.seekg(static_cast<std::streamoff>(file_size - 8));
    in.read(reinterpret_cast<char*>(tail), 8);
  }
  if (file_size < 16 || !in || std::memcmp(tail, kMagic, 8) != 0) {
    throw InputError(path_.string(), "truncated: the file of " + std::to_string(file_size) +
                                         " bytes does not end with the closing MCAP magic (cut short, or its "
                                         "writer stopped before closing it)");
  }
  in.seekg(8);
  // inner: the record's offset in its decompressed chunk, kNotInChunk for a record of the data section.
  auto records = [&](std::span<const std::uint8_t> content, std::uint8_t op, std::size_t offset, std::size_t inner) {
    const std::string where =
        (inner != kNotInChunk ? "record in the chunk at offset " : "record at offset ") + std::to_string(offset);
    Fields f(content, where);
    switch (op) {
      case Opcode::header:
        if (v.on_header) v.on_header(f.str());
        break;
      case Opcode::schema: {
        McapSchema s;
        s.id = f.num<std::uint16_t>();
        s.name = f.str();
        s.encoding = f.str();
        const auto data = f.bytes32();
        s.data.assign(data.begin(), data.end());
        if (v.on_schema) v.on_schema(s);
        break;
      }
      case Opcode::channel: {
        McapChannel c;
        c.id = f.num<std::uint16_t>();
        c.schema_id = f.num<std::uint16_t>();
        c.topic = f.str();
        c.message_encoding = f.str();
        if (v.on_channel) v.on_channel(c);
        break;
      }
      case Opcode::message: {
        McapMessage m;
        m.channel_id = f.num<std::uint16_t>();
        if (v.wants && !v.wants(m.channel_id)) break;
        m.sequence = f.num<std::uint32_t>();
        m.log_time = f.num<std::uint64_t>();
        m.publish_time = f.num<std::uint64_t>();
        m.data = f.rest();
        if (v.on_message) v.on_message(m, offset, inner);
        break;
      }
      default:
        break;
    }
  };
  std::uint64_t at = 8;
  std::vector<std::uint8_t> content;
  bool ended = false;
  while (!ended) {
    if (at == file_size) {
      throw InputError(path_.string(), "truncated: the file ends at byte " + std::to_string(at) +
                                           " without the MCAP footer and closing magic");
    }
    std::uint8_t head[9];
    in.read(reinterpret_cast<char*>(head), 9);
    if (!in || file_size - at < 9) {
      throw InputError(path_.string(), "truncated: the record header at offset " + std::to_string(at) +
                                           " runs past the end of the file");
    }
    const std::uint8_t op = head[0];
    std::uint64_t length = 0;
    std::memcpy(&length, head + 1, 8);
    if (length > file_size - at - 9) {
      throw InputError(path_.string(), "truncated: the record at offset " + std::to_string(at) + " (" +
                                           std::to_string(length) + " bytes) runs past the end of the " +
                                           std::to_string(file_size) + "-byte file");
    }
    const auto offset = static_cast<std::size_t>(at);
    at += 9 + length;
    if (op == Opcode::footer || op == Opcode::data_end) {
      ended = true;
      break;
    }
    if (op != Opcode::header && op != Opcode::schema && op != Opcode::channel && op != Opcode::message &&
        op != Opcode::chunk) {
      in.seekg(static_cast<std::streamoff>(at));
      continue;
    }
    content.resize(static_cast<std::size_t>(length));
    in.read(reinterpret_cast<char*>(content.data()), static_cast<std::streamsize>(length));
    if (!in) throw InputError(path_.string(), "cannot read the record at offset " + std::to_string(offset));
    try {
      if (op != Opcode::chunk) {
        records(content, op, offset, kNotInChunk);
        if (op == Opcode::header && v.stop_after_header) return;
        continue;
      }
      const std::string where = "chunk at offset " + std::to_string(offset);
      const std::vector<std::uint8_t> inner = unpack_chunk(content, where);
      std::size_t k = 0;
      while (k < inner.size()) {
        if (inner.size() - k < 9) throw std::invalid_argument(where + ": a record header runs past the chunk's end");
        std::uint64_t len = 0;
        std::memcpy(&len, inner.data() + k + 1, 8);
        if (len > inner.size() - k - 9) throw std::invalid_argument(where + ": a record runs past the chunk's end");
        records(std::span<const std::uint8_t>(inner).subspan(k + 9, static_cast<std::size_t>(len)), inner[k], offset,
                k);
        k += 9 + static_cast<std::size_t>(len);
      }
    } catch (const std::invalid_argument& e) {
      throw InputError(path_.string(), e.what());
    }
  }
}

bool McapReader::read_summary() {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return false;
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  constexpr std::uint64_t footer_record = 1 + 8 + 20;  // opcode, length, summary_start, offset start, crc
  if (size < 8 + footer_record + 8) return false;
  std::uint8_t footer_bytes[footer_record + 8];
  in.seekg(static_cast<std::streamoff>(size - footer_record - 8));
  in.read(reinterpret_cast<char*>(footer_bytes), sizeof footer_bytes);
  if (!in || footer_bytes[0] != Opcode::footer || std::memcmp(footer_bytes + footer_record, kMagic, 8) != 0)
    return false;
  std::uint64_t summary_start = 0;
  std::memcpy(&summary_start, footer_bytes + 9, 8);
  const std::uint64_t summary_end = size - footer_record - 8;
  if (summary_start == 0 || summary_start < 8 || summary_start > summary_end) return false;
  std::vector<std::uint8_t> summary(static_cast<std::size_t>(summary_end - summary_start));
  in.seekg(static_cast<std::streamoff>(summary_start));
  in.read(reinterpret_cast<char*>(summary.data()), static_cast<std::streamsize>(summary.size()));
  if (!in) return false;
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
  std::map<std::uint16_t, std::uint64_t> counts;
  bool have_statistics = false;
  std::uint64_t total = 0;
  try {
    std::size_t k = 0;
    while (k < summary.size()) {
      if (summary.size() - k < 9) return false;
      std::uint64_t len = 0;
      std::memcpy(&len, summary.data() + k + 1, 8);
      if (len > summary.size() - k - 9) return false;
      Fields f(std::span<const std::uint8_t>(summary).subspan(k + 9, static_cast<std::size_t>(len)), "summary");
      switch (summary[k]) {
        case Opcode::schema: {
          McapSchema sc;
          sc.id = f.num<std::uint16_t>();
          sc.name = f.str();
          sc.encoding = f.str();
          const auto data = f.bytes32();
          sc.data.assign(data.begin(), data.end());
          schemas[sc.id] = sc;
          break;
        }
        case Opcode::channel: {
          McapChannel c;
          c.id = f.num<std::uint16_t>();
          c.schema_id = f.num<std::uint16_t>();
          c.topic = f.str();
          c.message_encoding = f.str();
          channels[c.id] = c;
          break;
        }
        case Opcode::statistics: {
          total = f.num<std::uint64_t>();                            // message_count
          (void)f.num<std::uint16_t>();                              // schema_count
          for (int n = 0; n < 4; ++n) (void)f.num<std::uint32_t>();  // channel, attachment, metadata, chunk counts
          (void)f.num<std::uint64_t>();                              // message_start_time
          (void)f.num<std::uint64_t>();                              // message_end_time
          Fields map(f.bytes32(), "summary statistics");
          try {
            for (;;) {
              const auto id = map.num<std::uint16_t>();
              counts[id] = map.num<std::uint64_t>();
            }
          } catch (const std::invalid_argument&) {
            // end of the map
          }
          have_statistics = true;
          break;
        }
        default:
          break;
      }
      k += 9 + static_cast<std::size_t>(len);
    }
  } catch (const std::invalid_argument&) {
    return false;  // a summary that does not parse: read the data section instead
  }
  if (!have_statistics || channels.empty()) return false;
  // The channel counts are optional in the Statistics record: without them (or when they do not add up to its
  // message count) the data section is read for the counts.
  std::uint64_t sum = 0;
  for (const auto& [id, n] : counts) sum += n;
  if (sum != total) return false;
  for (const auto& [id, c] : channels) counts.try_emplace(id, 0);
  schemas_ = std::move(schemas);
  channels_ = std::move(channels);
  counts_ = std::move(counts);
  return true;
}

McapReader::McapReader(fs::path path) : path_(std::move(path)) {
  Visitor v;
  v.on_header = [&](const std::string& profile) { profile_ = profile; };
  v.on_schema = [&](const McapSchema& s) { schemas_[s.id] = s; };
  v.on_channel = [&](const McapChannel& c) {
    channels_[c.id] = c;
    counts_.try_emplace(c.id, 0);
  };
  v.on_message = [&](const McapMessage& m, std::size_t offset, std::size_t) {
    if (!channels_.count(m.channel_id)) {
      throw std::invalid_argument("message at offset " + std::to_string(offset) + " is on channel " +
                                  std::to_string(m.channel_id) + ", which no Channel record defines");
    }
    ++counts_[m.channel_id];
  };
  // The header (profile) and the checks of both magics come from the start of a scan; with a summary
  // (channels, schemas, statistics) the scan stops after the header instead of reading every chunk.
  const bool summary = read_summary();
  if (summary) {
    v.on_schema = nullptr;
    v.on_channel = nullptr;
    v.on_message = nullptr;
    v.stop_after_header = true;
  }
  scan(v);
}

void McapReader::for_each_message(const std::function<void(const McapChannel&, const McapMessage&)>& visit,
                                  const std::vector<std::uint16_t>& only) const {
  const auto wanted = [&](std::uint16_t id) {
    return only.empty() || std::find(only.begin(), only.end(), id) != only.end();
  };
  // First where each message is and when it was logged (no data kept), and the count of each channel checked
  // against the summary's (whose counts size the sequence before it is read).
  struct Place {
    std::uint64_t log_time;
    std::size_t offset, inner;
  };
  std::vector<Place> places;
  std::map<std::uint16_t, std::uint64_t> seen;
  {
    Visitor v;
    v.wants = wanted;
    v.on_message = [&](const McapMessage& m, std::size_t offset, std::size_t inner) {
      places.push_back({m.log_time, offset, inner});
      ++seen[m.channel_id];
    };
    scan(v);
  }
  for (const auto& [id, c] : channels_) {
    if (!wanted(id)) continue;
    const auto it = counts_.find(id);
    const std::uint64_t expected = it == counts_.end() ? 0 : it->second;
    const std::uint64_t got = seen.count(id) ? seen.at(id) : 0;
    if (got != expected) {
      throw InputError(path_.string(), "topic " + c.topic + ": the summary's Statistics record counts " +
                                           std::to_string(expected) + " messages, the data section holds " +
                                           std::to_string(got) + " (a damaged or rewritten MCAP file)");
    }
  }
  const auto by_time = [](const Place& a, const Place& b) { return a.log_time < b.log_time; };
  Visitor v;
  v.wants = wanted;
  v.on_message = [&](const McapMessage& m, std::size_t, std::size_t) {
    const auto it = channels_.find(m.channel_id);
    if (it != channels_.end()) visit(it->second, m);
  };
  if (std::is_sorted(places.begin(), places.end(), by_time)) {
    scan(v);  // the usual case: messages written in log-time order are streamed in one more pass
    return;
  }
  // Messages stored out of log-time order are visited in log-time order (ties in file order), each read where
  // it is; the last chunk decompressed is kept, so messages shuffled within chunks cost one decompression each.
  std::stable_sort(places.begin(), places.end(), by_time);
  std::ifstream in(path_, std::ios::binary);
  if (!in) throw InputError(path_.string(), "cannot open file");
  std::vector<std::uint8_t> record, chunk;
  std::size_t chunk_offset = kNotInChunk;
  const auto read_record = [&](std::size_t offset) {
    std::uint8_t head[9];
    in.seekg(static_cast<std::streamoff>(offset));
    in.read(reinterpret_cast<char*>(head), 9);
    std::uint64_t length = 0;
    std::memcpy(&length, head + 1, 8);
    record.resize(static_cast<std::size_t>(length));
    in.read(reinterpret_cast<char*>(record.data()), static_cast<std::streamsize>(length));
    if (!in) throw InputError(path_.string(), "cannot read the record at offset " + std::to_string(offset));
  };
  try {
    for (const Place& p : places) {
      std::span<const std::uint8_t> content;
      const std::string where = "record at offset " + std::to_string(p.offset);
      if (p.inner == kNotInChunk) {
        read_record(p.offset);
        content = record;
      } else {
        if (chunk_offset != p.offset) {
          read_record(p.offset);
          chunk = unpack_chunk(record, "chunk at offset " + std::to_string(p.offset));
          chunk_offset = p.offset;
        }
        std::uint64_t len = 0;
        std::memcpy(&len, chunk.data() + p.inner + 1, 8);
        content = std::span<const std::uint8_t>(chunk).subspan(p.inner + 9, static_cast<std::size_t>(len));
      }
      v.on_message(parse_message(content, where), p.offset, p.inner);
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(path_.string(), e.what());
  }
}

}  // namespace seqtopo::recording
