#pragma once
// A rosbag file, format 2.0 (wiki.ros.org/Bags/Format/2.0), written directly: uncompressed chunks buffered in memory
// and written whole, each followed by its connections' index records; at close the connection and chunk-info records
// and the file header pointing at them. rosbag's own writer seeks to the file's end before every message (fseeko on a
// read-write FILE: an lseek, a flush and a read of the last block), about 13 us a message; this costs a copy.
// ROS-free: the caller serialises the message (ros::serialization) into the room message() gives. A write error
// throws BagWriteError with the system's errno and leaves the writer closed; the file keeps what reached the disk,
// unindexed (`rosbag reindex`).
// One thread writes (the nodes write from their main loop; rosbag's writer locks, this one does not).
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace core {

struct BagWriteError : std::runtime_error {
  BagWriteError(const std::string& what, int err) : std::runtime_error(what), err(err) {}
  int err;  // errno of the failed call (0: none set)
};

class BagWriter {
 public:
  // chunk_bytes: a chunk is written once its records reach this size (rosbag's default, 768 KB: readers read one index
  // record per connection and chunk when they open a bag; a killed process loses at most the open chunk).
  explicit BagWriter(std::size_t chunk_bytes = 768 * 1024) : chunk_bytes_(chunk_bytes) {}
  ~BagWriter() { abandon(); }
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  void open(const std::string& path);  // creates or truncates; throws BagWriteError
  bool is_open() const { return fd_ >= 0; }
  // The connection of a topic and message type (the same pair: the same id), recorded in the bag with its first message.
  std::uint32_t connection(const std::string& topic, const std::string& type, const std::string& md5sum,
                           const std::string& definition);
  // Room for one message of `bytes` bytes on `conn` at time sec.nsec, valid until the next call: fill it at once.
  std::uint8_t* message(std::uint32_t conn, std::uint32_t sec, std::uint32_t nsec, std::uint32_t bytes);
  // Writes the open chunk and the index, and closes the file; throws BagWriteError (the file is then abandoned).
  void close();
  // Closes the file without its index (after a write error): it holds the chunks written so far.
  void abandon();

 private:
  struct Connection {
    std::string topic, type, md5sum, definition;
    bool recorded = false;  // its record is in a chunk already
  };
  struct Entry {
    std::uint32_t sec, nsec, offset;
  };
  struct ChunkInfo {
    std::uint64_t pos;
    std::uint32_t start_sec, start_nsec, end_sec, end_nsec;
    std::map<std::uint32_t, std::uint32_t> count;  // connection -> messages
  };
  void flush_chunk();
  void write_all(const std::vector<std::uint8_t>& bytes);
  void put_connection_record(std::vector<std::uint8_t>& out, std::uint32_t id) const;

  std::size_t chunk_bytes_;
  int fd_ = -1;
  std::string path_;
  std::uint64_t pos_ = 0;  // bytes in the file
  std::map<std::string, std::uint32_t> ids_;  // topic + '\n' + md5sum -> connection
  std::vector<Connection> conns_;
  std::vector<std::uint8_t> chunk_, out_;          // the open chunk's records; bytes on their way to the file
  std::map<std::uint32_t, std::vector<Entry>> index_;  // the open chunk's messages by connection
  std::uint32_t start_sec_ = 0, start_nsec_ = 0, end_sec_ = 0, end_nsec_ = 0;
  std::vector<ChunkInfo> chunks_;
};

}  // namespace core
