// core::BagWriter against the rosbag 2.0 format (wiki.ros.org/Bags/Format/2.0), read back record by record here.
// That rosbag's own readers (C++ View, Python) read its bags: test/ros/bag_writer.sh.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "core/bag_writer.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;

std::uint32_t u32(const std::uint8_t* p) { return p[0] | p[1] << 8 | p[2] << 16 | std::uint32_t(p[3]) << 24; }
std::uint64_t u64(const std::uint8_t* p) { return u32(p) | std::uint64_t(u32(p + 4)) << 32; }

struct Record {
  std::map<std::string, std::string> header;
  Bytes data;
  std::size_t pos = 0, data_pos = 0;
  std::uint8_t op() const { return static_cast<std::uint8_t>(header.at("op").at(0)); }
  std::uint32_t field32(const std::string& k) const { return u32(reinterpret_cast<const std::uint8_t*>(header.at(k).data())); }
  std::uint64_t field64(const std::string& k) const { return u64(reinterpret_cast<const std::uint8_t*>(header.at(k).data())); }
};

std::map<std::string, std::string> fields(const std::uint8_t* p, std::size_t n) {
  std::map<std::string, std::string> f;
  for (std::size_t i = 0; i < n;) {
    const std::uint32_t len = u32(p + i);
    const std::string kv(reinterpret_cast<const char*>(p + i + 4), len);
    const std::size_t eq = kv.find('=');
    EXPECT_NE(eq, std::string::npos);
    f[kv.substr(0, eq)] = kv.substr(eq + 1);
    i += 4 + len;
  }
  return f;
}

// The records from `pos` on, up to `end`.
std::vector<Record> records(const Bytes& b, std::size_t pos, std::size_t end) {
  std::vector<Record> out;
  while (pos < end) {
    Record r;
    r.pos = pos;
    const std::uint32_t hl = u32(&b[pos]);
    r.header = fields(&b[pos + 4], hl);
    const std::uint32_t dl = u32(&b[pos + 4 + hl]);
    r.data_pos = pos + 8 + hl;
    r.data.assign(b.begin() + r.data_pos, b.begin() + r.data_pos + dl);
    out.push_back(r);
    pos = r.data_pos + dl;
  }
  EXPECT_EQ(pos, end);
  return out;
}

// The one record at `pos`.
Record record_at(const Bytes& b, std::size_t pos) {
  const std::uint32_t hl = u32(&b[pos]);
  return records(b, pos, pos + 8 + hl + u32(&b[pos + 4 + hl]))[0];
}

Bytes read(const std::string& path) {  // the file's bytes; the file is removed
  std::ifstream f(path, std::ios::binary);
  Bytes b{std::istreambuf_iterator<char>(f), {}};
  std::remove(path.c_str());
  return b;
}

std::string tmp(const char* name) { return ::testing::TempDir() + std::to_string(::getpid()) + "_" + name; }

struct Msg {
  std::uint32_t conn, sec, nsec;
  std::string bytes;
};

// Writes msgs through the writer (chunk threshold `chunk`), returning the file's bytes.
Bytes write_bag(const std::string& path, const std::vector<Msg>& msgs, std::size_t chunk) {
  core::BagWriter w(chunk);
  w.open(path);
  EXPECT_EQ(w.connection("/a", "pkg/A", "0123456789abcdef0123456789abcdef", "int32 x\n"), 0u);
  EXPECT_EQ(w.connection("/b", "pkg/B", "fedcba9876543210fedcba9876543210", "float64 y\n"), 1u);
  EXPECT_EQ(w.connection("/a", "pkg/A", "0123456789abcdef0123456789abcdef", "int32 x\n"), 0u);  // the same pair
  for (const Msg& m : msgs) {
    std::uint8_t* p = w.message(m.conn, m.sec, m.nsec, static_cast<std::uint32_t>(m.bytes.size()));
    std::memcpy(p, m.bytes.data(), m.bytes.size());
  }
  w.close();
  return read(path);
}

}  // namespace

TEST(BagWriter, FileHeaderConnectionsChunksAndIndexFollowTheFormat) {
  std::vector<Msg> msgs;
  for (std::uint32_t i = 0; i < 40; ++i)  // two connections interleaved; one /b message out of time order
    msgs.push_back({i % 3 == 0 ? 1u : 0u, 10 + i / 10, i == 20 ? 5u : 1000u * i, std::string(7 + i, char('a' + i % 26))});
  const Bytes b = write_bag(tmp("fmt.bag"), msgs, 200);  // small chunks: several of them

  ASSERT_EQ(std::string(b.begin(), b.begin() + 13), "#ROSBAG V2.0\n");
  const Record head = record_at(b, 13);
  EXPECT_EQ(head.op(), 0x03);
  EXPECT_EQ(head.data_pos + head.data.size(), 13u + 4096 + 8);  // the header record padded to 4096 bytes
  const std::uint64_t index_pos = head.field64("index_pos");
  const std::uint32_t conn_count = head.field32("conn_count"), chunk_count = head.field32("chunk_count");
  EXPECT_EQ(conn_count, 2u);
  EXPECT_GT(chunk_count, 3u);

  // Chunks (each followed by one index record per connection in it) up to index_pos.
  const auto body = records(b, 13 + 4096 + 8, index_pos);
  std::vector<Msg> back;
  std::map<std::uint32_t, int> conn_records;
  std::size_t chunks = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    ASSERT_EQ(body[i].op(), 0x05);
    EXPECT_EQ(body[i].header.at("compression"), "none");
    EXPECT_EQ(body[i].field32("size"), body[i].data.size());
    ++chunks;
    std::map<std::uint32_t, std::vector<std::uint32_t>> offsets;  // by connection, in record order
    for (const Record& r : records(body[i].data, 0, body[i].data.size())) {
      if (r.op() == 0x07) {
        ++conn_records[r.field32("conn")];
        continue;
      }
      ASSERT_EQ(r.op(), 0x02);
      const std::uint64_t t = r.field64("time");
      back.push_back({r.field32("conn"), std::uint32_t(t), std::uint32_t(t >> 32), std::string(r.data.begin(), r.data.end())});
      offsets[r.field32("conn")].push_back(static_cast<std::uint32_t>(r.pos));
    }
    for (std::size_t k = 0; k < offsets.size(); ++k) {  // the index records, one per connection, ascending
      const Record& ix = body[++i];
      ASSERT_EQ(ix.op(), 0x04);
      EXPECT_EQ(ix.field32("ver"), 1u);
      const std::uint32_t conn = ix.field32("conn"), n = ix.field32("count");
      ASSERT_EQ(n, offsets.at(conn).size());
      ASSERT_EQ(ix.data.size(), 12u * n);
      std::vector<std::uint32_t> at;
      for (std::uint32_t e = 0; e < n; ++e) {
        const std::uint32_t sec = u32(&ix.data[12 * e]), nsec = u32(&ix.data[12 * e + 4]), off = u32(&ix.data[12 * e + 8]);
        at.push_back(off);
        // the entry points at a message record of that connection and time
        const Record m = record_at(body[i - k - 1].data, off);
        EXPECT_EQ(m.field32("conn"), conn);
        EXPECT_EQ(m.field64("time"), std::uint64_t(nsec) << 32 | sec);
        if (e > 0) {  // in time order
          const std::uint32_t s0 = u32(&ix.data[12 * (e - 1)]), n0 = u32(&ix.data[12 * (e - 1) + 4]);
          EXPECT_FALSE(sec < s0 || (sec == s0 && nsec < n0));
        }
      }
      std::sort(at.begin(), at.end());
      EXPECT_EQ(at, offsets.at(conn));
    }
  }
  EXPECT_EQ(chunks, chunk_count);
  ASSERT_EQ(back.size(), msgs.size());  // every message, in order, byte for byte
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    EXPECT_EQ(back[i].conn, msgs[i].conn);
    EXPECT_EQ(back[i].sec, msgs[i].sec);
    EXPECT_EQ(back[i].nsec, msgs[i].nsec);
    EXPECT_EQ(back[i].bytes, msgs[i].bytes);
  }
  EXPECT_EQ(conn_records, (std::map<std::uint32_t, int>{{0, 1}, {1, 1}}));  // each once, with its first message

  // The index: the connections, then one chunk info per chunk.
  const auto tail = records(b, index_pos, b.size());
  ASSERT_EQ(tail.size(), conn_count + chunk_count);
  for (std::uint32_t c = 0; c < conn_count; ++c) {
    ASSERT_EQ(tail[c].op(), 0x07);
    EXPECT_EQ(tail[c].field32("conn"), c);
    const auto d = fields(tail[c].data.data(), tail[c].data.size());
    EXPECT_EQ(tail[c].header.at("topic"), c == 0 ? "/a" : "/b");
    EXPECT_EQ(d.at("topic"), tail[c].header.at("topic"));
    EXPECT_EQ(d.at("type"), c == 0 ? "pkg/A" : "pkg/B");
    EXPECT_EQ(d.at("md5sum"), c == 0 ? "0123456789abcdef0123456789abcdef" : "fedcba9876543210fedcba9876543210");
    EXPECT_EQ(d.at("message_definition"), c == 0 ? "int32 x\n" : "float64 y\n");
  }
  std::uint32_t total = 0;
  for (std::uint32_t k = 0; k < chunk_count; ++k) {
    const Record& ci = tail[conn_count + k];
    ASSERT_EQ(ci.op(), 0x06);
    EXPECT_EQ(ci.field32("ver"), 1u);
    const auto at = std::find_if(body.begin(), body.end(), [&](const Record& r) { return r.pos == ci.field64("chunk_pos"); });
    ASSERT_NE(at, body.end());  // chunk_pos: where a chunk record starts
    const Record& chunk = *at;
    ASSERT_EQ(chunk.op(), 0x05);
    // start and end: the chunk's earliest and latest message times
    std::uint64_t lo = ~0ull, hi = 0;
    for (const Record& r : records(chunk.data, 0, chunk.data.size()))
      if (r.op() == 0x02) {
        const std::uint64_t t = r.field64("time"), key = (t & 0xffffffffull) << 32 | t >> 32;  // (sec, nsec) order
        lo = std::min(lo, key), hi = std::max(hi, key);
      }
    const std::uint64_t s = ci.field64("start_time"), e = ci.field64("end_time");
    EXPECT_EQ((s & 0xffffffffull) << 32 | s >> 32, lo);
    EXPECT_EQ((e & 0xffffffffull) << 32 | e >> 32, hi);
    const std::uint32_t n = ci.field32("count");
    ASSERT_EQ(ci.data.size(), 8u * n);
    for (std::uint32_t c = 0; c < n; ++c) total += u32(&ci.data[8 * c + 4]);
  }
  EXPECT_EQ(total, msgs.size());
}

TEST(BagWriter, AnEmptyBagIsIndexedWithNothingInIt) {
  core::BagWriter w;
  w.open(tmp("empty.bag"));
  w.close();
  const Bytes b = read(tmp("empty.bag"));
  ASSERT_EQ(b.size(), 13u + 4096 + 8);
  const Record head = record_at(b, 13);
  EXPECT_EQ(head.field64("index_pos"), b.size());
  EXPECT_EQ(head.field32("conn_count"), 0u);
  EXPECT_EQ(head.field32("chunk_count"), 0u);
}

TEST(BagWriter, AWriteErrorThrowsWithTheSystemsReasonAndKeepsTheWrittenChunks) {
  std::signal(SIGXFSZ, SIG_IGN);  // a write past the size limit fails with EFBIG instead of killing the process
  rlimit old{};
  getrlimit(RLIMIT_FSIZE, &old);
  rlimit small = old;
  small.rlim_cur = 20000;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  int err = -1;
  std::size_t written = 0;
  {
    core::BagWriter w(1000);
    w.open(tmp("limit.bag"));
    const std::uint32_t c = w.connection("/a", "pkg/A", "0123456789abcdef0123456789abcdef", "int32 x\n");
    try {
      for (std::uint32_t i = 0; i < 1000; ++i, ++written) std::memset(w.message(c, 1, i, 100), 7, 100);
    } catch (const core::BagWriteError& e) {
      err = e.err;
      EXPECT_NE(std::string(e.what()).find("bytes at offset"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(w.is_open());
    EXPECT_THROW(w.message(c, 2, 0, 1), core::BagWriteError);  // abandoned: no more writes
  }
  setrlimit(RLIMIT_FSIZE, &old);
  EXPECT_EQ(err, EFBIG);
  EXPECT_GT(written, 80u);  // 142 bytes a message: 15,883 bytes of room after the file header
  const Bytes b = read(tmp("limit.bag"));
  EXPECT_LE(b.size(), 20000u);
  EXPECT_EQ(record_at(b, 13).field64("index_pos"), 0u);  // unindexed: `rosbag reindex` mends it
}
