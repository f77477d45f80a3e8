#include "core/bag_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace core {
namespace {

// Record op codes and the file header's size (the format's spec).
constexpr std::uint8_t kOpMessage = 0x02, kOpFileHeader = 0x03, kOpIndex = 0x04, kOpChunk = 0x05, kOpChunkInfo = 0x06,
                       kOpConnection = 0x07;
constexpr std::uint32_t kFileHeaderBytes = 4096;  // header + padding of the file header record
constexpr char kVersion[] = "#ROSBAG V2.0\n";

void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));  // little-endian
}
void set_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// A header: fields "name=value", each after its length; the whole after its length.
struct Header {
  std::vector<std::uint8_t> b;
  Header() { put_u32(b, 0); }
  Header& field(const char* name, const void* value, std::size_t n) {
    const std::size_t k = std::strlen(name);
    put_u32(b, static_cast<std::uint32_t>(k + 1 + n));
    b.insert(b.end(), name, name + k);
    b.push_back('=');
    b.insert(b.end(), static_cast<const std::uint8_t*>(value), static_cast<const std::uint8_t*>(value) + n);
    return *this;
  }
  Header& u8(const char* name, std::uint8_t v) { return field(name, &v, 1); }
  Header& u32(const char* name, std::uint32_t v) {
    std::uint8_t x[4];
    set_u32(x, v);
    return field(name, x, 4);
  }
  Header& u64(const char* name, std::uint64_t v) {
    std::uint8_t x[8];
    set_u32(x, static_cast<std::uint32_t>(v)), set_u32(x + 4, static_cast<std::uint32_t>(v >> 32));
    return field(name, x, 8);
  }
  Header& time(const char* name, std::uint32_t sec, std::uint32_t nsec) {  // sec then nsec
    return u64(name, (static_cast<std::uint64_t>(nsec) << 32) | sec);
  }
  Header& str(const char* name, const std::string& s) { return field(name, s.data(), s.size()); }
  const std::vector<std::uint8_t>& done() {
    set_u32(b.data(), static_cast<std::uint32_t>(b.size() - 4));
    return b;
  }
};

void append(std::vector<std::uint8_t>& out, const std::vector<std::uint8_t>& b) { out.insert(out.end(), b.begin(), b.end()); }

// The file header record, padded to its fixed size.
std::vector<std::uint8_t> file_header(std::uint64_t index_pos, std::uint32_t conns, std::uint32_t chunks) {
  Header h;
  const auto& hb = h.u8("op", kOpFileHeader).u64("index_pos", index_pos).u32("conn_count", conns).u32("chunk_count", chunks).done();
  std::vector<std::uint8_t> out(hb);
  const std::uint32_t pad = kFileHeaderBytes - static_cast<std::uint32_t>(hb.size() - 4);
  put_u32(out, pad);
  out.insert(out.end(), pad, ' ');
  return out;
}

bool before(const std::uint32_t s0, std::uint32_t n0, std::uint32_t s1, std::uint32_t n1) {
  return s0 < s1 || (s0 == s1 && n0 < n1);
}

}  // namespace

void BagWriter::open(const std::string& path) {
  abandon();
  path_ = path;
  errno = 0;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) throw BagWriteError("cannot create it", errno);
  ids_.clear(), conns_.clear(), chunk_.clear(), index_.clear(), chunks_.clear();
  pos_ = 0;
  out_.assign(kVersion, kVersion + sizeof kVersion - 1);
  append(out_, file_header(0, 0, 0));  // index_pos 0 (unindexed) until close
  write_all(out_);
}

std::uint32_t BagWriter::connection(const std::string& topic, const std::string& type, const std::string& md5sum,
                                   const std::string& definition) {
  const auto [it, added] = ids_.emplace(topic + '\n' + md5sum, static_cast<std::uint32_t>(conns_.size()));
  if (added) conns_.push_back({topic, type, md5sum, definition});
  return it->second;
}

void BagWriter::put_connection_record(std::vector<std::uint8_t>& out, std::uint32_t id) const {
  const Connection& c = conns_[id];
  Header h, d;
  append(out, h.u8("op", kOpConnection).u32("conn", id).str("topic", c.topic).done());
  append(out, d.str("topic", c.topic).str("type", c.type).str("md5sum", c.md5sum).str("message_definition", c.definition).done());
}

std::uint8_t* BagWriter::message(std::uint32_t conn, std::uint32_t sec, std::uint32_t nsec, std::uint32_t bytes) {
  if (fd_ < 0) throw BagWriteError("the bag is not open", 0);
  if (conn >= conns_.size()) throw std::invalid_argument("BagWriter::message: unknown connection");
  if (chunk_.size() >= chunk_bytes_) flush_chunk();
  if (!conns_[conn].recorded) put_connection_record(chunk_, conn), conns_[conn].recorded = true;
  if (index_.empty() || before(sec, nsec, start_sec_, start_nsec_)) start_sec_ = sec, start_nsec_ = nsec;
  if (index_.empty() || before(end_sec_, end_nsec_, sec, nsec)) end_sec_ = sec, end_nsec_ = nsec;
  index_[conn].push_back({sec, nsec, static_cast<std::uint32_t>(chunk_.size())});
  Header h;
  append(chunk_, h.u8("op", kOpMessage).u32("conn", conn).time("time", sec, nsec).done());
  put_u32(chunk_, bytes);
  chunk_.resize(chunk_.size() + bytes);
  return chunk_.data() + chunk_.size() - bytes;
}

// The open chunk (records as they are: compression none), then one index record per connection in it.
void BagWriter::flush_chunk() {
  if (chunk_.empty()) return;
  ChunkInfo info{pos_, start_sec_, start_nsec_, end_sec_, end_nsec_, {}};
  out_.clear();
  Header h;
  append(out_, h.u8("op", kOpChunk).str("compression", "none").u32("size", static_cast<std::uint32_t>(chunk_.size())).done());
  put_u32(out_, static_cast<std::uint32_t>(chunk_.size()));
  append(out_, chunk_);
  for (auto& [conn, entries] : index_) {
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return before(a.sec, a.nsec, b.sec, b.nsec); });
    Header ih;
    append(out_, ih.u8("op", kOpIndex).u32("ver", 1).u32("conn", conn).u32("count", static_cast<std::uint32_t>(entries.size())).done());
    put_u32(out_, static_cast<std::uint32_t>(12 * entries.size()));
    for (const Entry& e : entries) put_u32(out_, e.sec), put_u32(out_, e.nsec), put_u32(out_, e.offset);
    info.count[conn] = static_cast<std::uint32_t>(entries.size());
  }
  chunk_.clear();
  index_.clear();
  chunks_.push_back(std::move(info));
  write_all(out_);
}

void BagWriter::write_all(const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    errno = 0;
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = errno;
      abandon();
      throw BagWriteError("writing " + std::to_string(bytes.size() - done) + " bytes at offset " +
                              std::to_string(pos_ + done),
                          err);
    }
    done += static_cast<std::size_t>(n);
  }
  pos_ += bytes.size();
}

void BagWriter::close() {
  if (fd_ < 0) return;
  flush_chunk();
  const std::uint64_t index_pos = pos_;
  out_.clear();
  for (std::uint32_t id = 0; id < conns_.size(); ++id) put_connection_record(out_, id);
  for (const ChunkInfo& c : chunks_) {
    Header h;
    append(out_, h.u8("op", kOpChunkInfo)
                     .u32("ver", 1)
                     .u64("chunk_pos", c.pos)
                     .time("start_time", c.start_sec, c.start_nsec)
                     .time("end_time", c.end_sec, c.end_nsec)
                     .u32("count", static_cast<std::uint32_t>(c.count.size()))
                     .done());
    put_u32(out_, static_cast<std::uint32_t>(8 * c.count.size()));
    for (const auto& [conn, n] : c.count) put_u32(out_, conn), put_u32(out_, n);
  }
  write_all(out_);
  const std::vector<std::uint8_t> head =
      file_header(index_pos, static_cast<std::uint32_t>(conns_.size()), static_cast<std::uint32_t>(chunks_.size()));
  errno = 0;
  const ssize_t n = ::pwrite(fd_, head.data(), head.size(), sizeof kVersion - 1);
  if (n != static_cast<ssize_t>(head.size())) {
    const int err = errno;
    abandon();
    throw BagWriteError("writing the file header (the index's position)", err);
  }
  errno = 0;
  const int rc = ::close(fd_);
  fd_ = -1;
  if (rc != 0) throw BagWriteError("closing it", errno);
}

void BagWriter::abandon() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace core
