#include "workspace_proximity/replay/bag_check.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

#include <bzlib.h>
#include <roslz4/lz4s.h>

#include "workspace_proximity/replay/bag_input.hpp"

namespace workspace_proximity {
namespace {

// Record opcodes of the bag format 2.0.
constexpr std::uint8_t kOpMessage = 0x02;
constexpr std::uint8_t kOpBagHeader = 0x03;
constexpr std::uint8_t kOpIndexData = 0x04;
constexpr std::uint8_t kOpChunk = 0x05;
constexpr std::uint8_t kOpChunkInfo = 0x06;
constexpr std::uint8_t kOpConnection = 0x07;

// A chunk may hold one large message, so no fixed size; but a damaged size must not make us
// allocate gigabytes: at most 2 GiB, and at most 1000 times its compressed bytes.
constexpr std::uint64_t kMaxChunk = std::uint64_t{2} << 30;

using Fields = std::map<std::string, std::string>;

struct Time {
  std::uint32_t sec = 0, nsec = 0;
  bool operator<(const Time& o) const { return sec != o.sec ? sec < o.sec : nsec < o.nsec; }
  bool operator==(const Time& o) const { return sec == o.sec && nsec == o.nsec; }
};

class Damaged {
 public:
  explicit Damaged(const std::string& path) : path_(path) {}
  [[noreturn]] void operator()(std::uint64_t byte, const std::string& what) const {
    fail("damaged at byte ", byte, what);
  }
  /// A record that runs past the end of the file: most likely a copy cut short.
  [[noreturn]] void cut(std::uint64_t byte, const std::string& what) const {
    fail("truncated or damaged at byte ", byte, what);
  }

 private:
  [[noreturn]] void fail(const char* prefix, std::uint64_t byte, const std::string& what) const {
    std::ostringstream s;
    s << prefix << byte << ": " << what;
    throw ReplayError(ReplayError::kBag, "bag " + path_ + ": " + s.str());
  }
  std::string path_;
};

std::uint32_t u32(const char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

std::uint64_t u64(const char* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
}

// A record header's fields ("<u32 len>name=value" ...); false when malformed.
bool parseFields(const char* p, std::size_t len, Fields* out) {
  out->clear();
  std::size_t at = 0;
  while (at < len) {
    if (len - at < 4) return false;
    const std::uint32_t n = u32(p + at);
    at += 4;
    if (n > len - at) return false;
    const char* field = p + at;
    const char* eq = static_cast<const char*>(std::memchr(field, '=', n));
    if (eq == nullptr) return false;
    (*out)[std::string(field, eq)] = std::string(eq + 1, field + n);
    at += n;
  }
  return true;
}

bool fieldU8(const Fields& f, const char* name, std::uint8_t* v) {
  auto it = f.find(name);
  if (it == f.end() || it->second.size() != 1) return false;
  *v = static_cast<std::uint8_t>(it->second[0]);
  return true;
}

bool fieldU32(const Fields& f, const char* name, std::uint32_t* v) {
  auto it = f.find(name);
  if (it == f.end() || it->second.size() != 4) return false;
  *v = u32(it->second.data());
  return true;
}

bool fieldU64(const Fields& f, const char* name, std::uint64_t* v) {
  auto it = f.find(name);
  if (it == f.end() || it->second.size() != 8) return false;
  *v = u64(it->second.data());
  return true;
}

bool fieldTime(const Fields& f, const char* name, Time* t) {
  auto it = f.find(name);
  if (it == f.end() || it->second.size() != 8) return false;
  t->sec = u32(it->second.data());
  t->nsec = u32(it->second.data() + 4);
  return true;
}

// A record of the file: its header fields and where its data is.
struct Record {
  std::uint64_t pos = 0;
  Fields fields;
  std::uint8_t op = 0;
  std::uint64_t data_pos = 0;
  std::uint32_t data_len = 0;
  std::uint64_t end() const { return data_pos + data_len; }
};

class BagFile {
 public:
  BagFile(const std::string& path, const Damaged& damaged) : damaged_(damaged) {
    in_.open(path, std::ios::binary);
    if (!in_) throw ReplayError(ReplayError::kBag, "bag " + path + ": cannot open the file (no such file, or not readable)");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<std::uint64_t>(in_.tellg());
  }
  std::uint64_t size() const { return size_; }

  bool read(std::uint64_t pos, void* out, std::uint64_t n) {
    if (pos > size_ || n > size_ - pos) return false;
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(pos));
    in_.read(static_cast<char*>(out), static_cast<std::streamsize>(n));
    return static_cast<std::uint64_t>(in_.gcount()) == n;
  }

  // The record at `pos`; `what` names it in messages.
  Record record(std::uint64_t pos, const char* what) {
    Record r;
    r.pos = pos;
    char len[4];
    if (!read(pos, len, 4)) damaged_.cut(pos, std::string(what) + " is cut off (the file ends)");
    const std::uint32_t header_len = u32(len);
    if (header_len > size_ - pos - 4) damaged_.cut(pos, std::string(what) + ": header runs past the end of the file");
    header_.resize(header_len);
    if (!read(pos + 4, &header_[0], header_len)) damaged_(pos, std::string(what) + ": unreadable header");
    if (!parseFields(header_.data(), header_.size(), &r.fields) || !fieldU8(r.fields, "op", &r.op)) {
      damaged_(pos, std::string(what) + ": malformed header");
    }
    if (!read(pos + 4 + header_len, len, 4)) damaged_.cut(pos, std::string(what) + " is cut off (the file ends)");
    r.data_len = u32(len);
    r.data_pos = pos + 8 + header_len;
    if (r.data_len > size_ - r.data_pos) damaged_.cut(pos, std::string(what) + ": data runs past the end of the file");
    return r;
  }

 private:
  const Damaged& damaged_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::string header_;
};

struct ChunkInfo {
  std::uint64_t info_pos = 0;
  std::uint64_t chunk_pos = 0;
  Time start, end;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> counts;  // connection, messages
};

}  // namespace

BagStructure checkBagStructure(const std::string& path) {
  const Damaged damaged(path);
  BagFile file(path, damaged);
  auto fail = [&](const std::string& what) -> ReplayError {
    return ReplayError(ReplayError::kBag, "bag " + path + ": " + what);
  };

  char magic[13] = {};
  const bool whole_magic = file.read(0, magic, sizeof(magic));
  const std::string version(magic, whole_magic ? sizeof(magic) : 0);
  if (!whole_magic || version.compare(0, 9, "#ROSBAG V") != 0) {
    throw fail("not a ROS bag (it does not start with #ROSBAG)");
  }
  if (version != "#ROSBAG V2.0\n") return BagStructure();  // older formats: rosbag says what it can do

  // The file header record: where the index is, how many connections and chunks.
  const Record header = file.record(sizeof(magic), "the file header");
  std::uint64_t index_pos = 0;
  BagStructure s;
  if (header.op != kOpBagHeader || !fieldU64(header.fields, "index_pos", &index_pos) ||
      !fieldU32(header.fields, "conn_count", &s.connections) ||
      !fieldU32(header.fields, "chunk_count", &s.chunks)) {
    damaged(header.pos, "the file header lacks the index position or counts");
  }
  if (index_pos == 0) {
    throw fail("not indexed: the recording was not closed (interrupted recorder); `rosbag reindex " +
               path + "` rebuilds the index");
  }
  if (index_pos >= file.size()) {
    std::ostringstream m;
    m << "truncated: its index should start at byte " << index_pos << " but the file has only "
      << file.size() << " bytes (an incomplete copy?); `rosbag reindex` may recover the complete part";
    throw fail(m.str());
  }

  // The index: every connection, then one chunk info per chunk.
  std::set<std::uint32_t> connections;
  std::uint64_t pos = index_pos;
  for (std::uint32_t i = 0; i < s.connections; ++i) {
    const Record r = file.record(pos, "a connection record of the index");
    std::uint32_t conn = 0;
    if (r.op != kOpConnection || !fieldU32(r.fields, "conn", &conn)) {
      damaged(pos, "expected connection record " + std::to_string(i + 1) + " of " +
                       std::to_string(s.connections) + " (truncated or damaged index)");
    }
    connections.insert(conn);
    pos = r.end();
  }
  std::vector<ChunkInfo> infos;
  std::vector<char> data;
  for (std::uint32_t i = 0; i < s.chunks; ++i) {
    const Record r = file.record(pos, "a chunk info record of the index");
    ChunkInfo info;
    info.info_pos = pos;
    std::uint32_t ver = 0, count = 0;
    if (r.op != kOpChunkInfo || !fieldU32(r.fields, "ver", &ver) || ver != 1 ||
        !fieldU64(r.fields, "chunk_pos", &info.chunk_pos) || !fieldTime(r.fields, "start_time", &info.start) ||
        !fieldTime(r.fields, "end_time", &info.end) || !fieldU32(r.fields, "count", &count) ||
        r.data_len != std::uint64_t{count} * 8) {
      damaged(pos, "expected chunk info " + std::to_string(i + 1) + " of " + std::to_string(s.chunks) +
                       " (truncated or damaged index)");
    }
    if (info.end < info.start || info.chunk_pos >= index_pos) damaged(pos, "chunk info with an impossible time range or position");
    data.resize(r.data_len);
    if (!file.read(r.data_pos, data.data(), r.data_len)) damaged(pos, "unreadable chunk info");
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t conn = u32(data.data() + 8 * k);
      if (connections.count(conn) == 0) damaged(pos, "chunk info names connection " + std::to_string(conn) + ", which the index does not have");
      info.counts.emplace_back(conn, u32(data.data() + 8 * k + 4));
    }
    infos.push_back(std::move(info));
    pos = r.end();
  }

  // Each chunk: its records inside, then the index records after it.
  std::vector<char> compressed, chunk;
  std::unordered_map<std::uint32_t, std::pair<std::uint32_t, Time>> messages;  // offset -> conn, time
  Fields fields;
  for (std::size_t c = 0; c < infos.size(); ++c) {
    const ChunkInfo& info = infos[c];
    const std::string which = "chunk " + std::to_string(c + 1) + " of " + std::to_string(infos.size());
    const Record r = file.record(info.chunk_pos, which.c_str());
    std::uint32_t size = 0;
    auto compression = r.fields.find("compression");
    if (r.op != kOpChunk || compression == r.fields.end() || !fieldU32(r.fields, "size", &size)) {
      damaged(info.chunk_pos, which + ": not a chunk record");
    }
    const std::string& how = compression->second;
    if (how == "none") {
      if (size != r.data_len) damaged(info.chunk_pos, which + ": its size does not match its data");
      chunk.resize(size);
      if (!file.read(r.data_pos, chunk.data(), size)) damaged(r.data_pos, which + ": unreadable");
    } else if (how == "bz2" || how == "lz4") {
      if (size > kMaxChunk || size > std::uint64_t{r.data_len} * 1000 + (1 << 20)) {
        damaged(info.chunk_pos, which + ": implausible uncompressed size " + std::to_string(size));
      }
      compressed.resize(r.data_len);
      if (!file.read(r.data_pos, compressed.data(), r.data_len)) damaged(r.data_pos, which + ": unreadable");
      chunk.resize(size);
      unsigned int out = size;
      const bool ok = how == "bz2"
          ? BZ2_bzBuffToBuffDecompress(chunk.data(), &out, compressed.data(), r.data_len, 0, 0) == BZ_OK
          : roslz4_buffToBuffDecompress(compressed.data(), r.data_len, chunk.data(), &out) == ROSLZ4_OK;
      if (!ok || out != size) damaged(r.data_pos, which + ": its " + how + " data does not decompress to its size");
    } else {
      damaged(info.chunk_pos, which + ": unknown compression '" + how + "'");
    }

    // The records inside the chunk: message data and connections.
    messages.clear();
    for (std::uint64_t at = 0; at < chunk.size();) {
      const std::uint64_t left = chunk.size() - at;
      std::uint32_t header_len = left >= 4 ? u32(chunk.data() + at) : 0;
      if (left < 4 || header_len > left - 4 || left - 4 - header_len < 4 ||
          !parseFields(chunk.data() + at + 4, header_len, &fields)) {
        damaged(r.data_pos, which + ": a record at offset " + std::to_string(at) + " in it is cut off or malformed");
      }
      const std::uint32_t data_len = u32(chunk.data() + at + 4 + header_len);
      if (data_len > left - 8 - header_len) {
        damaged(r.data_pos, which + ": a record at offset " + std::to_string(at) + " runs past the chunk's end");
      }
      std::uint8_t op = 0;
      std::uint32_t conn = 0;
      Time time;
      if (!fieldU8(fields, "op", &op) || !fieldU32(fields, "conn", &conn) ||
          (op != kOpMessage && op != kOpConnection) ||
          (op == kOpMessage && !fieldTime(fields, "time", &time))) {
        damaged(r.data_pos, which + ": a record at offset " + std::to_string(at) + " is neither a message nor a connection");
      }
      if (op == kOpMessage) messages[static_cast<std::uint32_t>(at)] = {conn, time};
      at += 8 + std::uint64_t{header_len} + data_len;
    }

    // One index record per connection of the chunk, each entry pointing at a message record.
    std::uint64_t index_at = r.end();
    std::set<std::uint32_t> indexed;
    for (std::size_t k = 0; k < info.counts.size(); ++k) {
      const Record ix = file.record(index_at, ("the index after " + which).c_str());
      std::uint32_t ver = 0, conn = 0, count = 0;
      if (ix.op != kOpIndexData || !fieldU32(ix.fields, "ver", &ver) || ver != 1 ||
          !fieldU32(ix.fields, "conn", &conn) || !fieldU32(ix.fields, "count", &count) ||
          ix.data_len != std::uint64_t{count} * 12) {
        damaged(index_at, "the index after " + which + " is malformed");
      }
      auto expected = std::find_if(info.counts.begin(), info.counts.end(),
                                   [&](const std::pair<std::uint32_t, std::uint32_t>& p) { return p.first == conn; });
      if (expected == info.counts.end() || expected->second != count || !indexed.insert(conn).second) {
        damaged(index_at, "the index after " + which + " does not match its chunk info");
      }
      data.resize(ix.data_len);
      if (!file.read(ix.data_pos, data.data(), ix.data_len)) damaged(ix.data_pos, "unreadable index");
      for (std::uint32_t e = 0; e < count; ++e) {
        const char* entry = data.data() + 12 * e;
        const Time t{u32(entry), u32(entry + 4)};
        const std::uint32_t offset = u32(entry + 8);
        auto m = messages.find(offset);
        if (m == messages.end() || m->second.first != conn || !(m->second.second == t) ||
            t < info.start || info.end < t) {
          damaged(ix.data_pos + 12 * e, "index entry " + std::to_string(e + 1) + " after " + which +
                                            " does not point at its message (or has another time)");
        }
      }
      s.messages += count;
      index_at = ix.end();
    }
  }
  return s;
}

}  // namespace workspace_proximity
