#pragma once
// Binary state files (checkpoints): raw little-endian values in a fixed order, each block opened by a
// 4-character tag so that a file written by another version or for another object fails loudly at the
// first mismatch instead of loading garbage. Doubles are written bit for bit (a restored run continues
// exactly). ROS-free.
#include <cstdint>
#include <cstring>
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace core {

class BinaryWriter {
 public:
  explicit BinaryWriter(std::ostream& os) : os_(os) {}
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable<T>::value, "put: trivially copyable types only");
    os_.write(reinterpret_cast<const char*>(&v), sizeof(T));
    if (!os_) throw std::runtime_error("checkpoint: write failed (disk full?)");
  }
  // Vectors of trivially copyable elements (any allocator): count, then the raw elements.
  template <class T, class A>
  void put_vec(const std::vector<T, A>& v) {
    static_assert(std::is_trivially_copyable<T>::value, "put_vec: trivially copyable elements only");
    put<uint64_t>(v.size());
    if (!v.empty()) os_.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
    if (!os_) throw std::runtime_error("checkpoint: write failed (disk full?)");
  }
  // Three (or n) doubles of anything indexable: Eigen vectors, std::array, raw arrays.
  template <class V>
  void put_xyz(const V& v) {
    for (int k = 0; k < 3; ++k) put<double>(v[k]);
  }
  void put_doubles(const double* v, int n) {
    for (int k = 0; k < n; ++k) put<double>(v[k]);
  }
  void put_string(const std::string& s) {
    put<uint64_t>(s.size());
    os_.write(s.data(), std::streamsize(s.size()));
    if (!os_) throw std::runtime_error("checkpoint: write failed (disk full?)");
  }
  // Block tag: exactly 4 characters, e.g. "WRLD".
  void tag(const char* t) { os_.write(t, 4); }

 private:
  std::ostream& os_;
};

class BinaryReader {
 public:
  // `what` names the file in error messages.
  BinaryReader(std::istream& is, std::string what) : is_(is), what_(std::move(what)) {}
  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable<T>::value, "get: trivially copyable types only");
    T v;
    read(reinterpret_cast<char*>(&v), sizeof(T));
    return v;
  }
  template <class T>
  void get(T& v) { v = get<T>(); }
  template <class T, class A>
  void get_vec(std::vector<T, A>& v, uint64_t max_count = uint64_t(1) << 34) {
    static_assert(std::is_trivially_copyable<T>::value, "get_vec: trivially copyable elements only");
    const uint64_t n = get<uint64_t>();
    if (n > max_count) fail("implausible array length " + std::to_string(n));
    const auto left = bytes_left();
    if (left >= 0 && n * sizeof(T) > static_cast<uint64_t>(left))
      fail("array of " + std::to_string(n) + " entries runs past the end of the file (truncated or corrupt)");
    v.resize(n);
    if (n) read(reinterpret_cast<char*>(v.data()), n * sizeof(T));
  }
  template <class V>
  V get_xyz() {
    V v;
    for (int k = 0; k < 3; ++k) v[k] = get<double>();
    return v;
  }
  void get_doubles(double* v, int n) {
    for (int k = 0; k < n; ++k) v[k] = get<double>();
  }
  std::string get_string() {
    const uint64_t n = get<uint64_t>();
    if (n > (uint64_t(1) << 20)) fail("implausible string length " + std::to_string(n));
    std::string s(n, '\0');
    if (n) read(&s[0], n);
    return s;
  }
  // Reads 4 characters and throws std::runtime_error unless they are `t`.
  void expect(const char* t) {
    char got[5] = {0, 0, 0, 0, 0};
    read(got, 4);
    if (std::memcmp(got, t, 4) != 0)
      fail(std::string("expected block '") + std::string(t, 4) + "', found '" + got +
           "' (written by another version, or for another configuration)");
  }
  [[noreturn]] void fail(const std::string& msg) const {
    throw std::runtime_error("checkpoint " + what_ + ": " + msg);
  }
  const std::string& what() const { return what_; }
  // Bytes from here to the end, or -1 when the stream cannot tell.
  std::streamoff bytes_left() {
    const auto here = is_.tellg();
    if (here < 0) return -1;
    is_.seekg(0, std::ios::end);
    const auto end = is_.tellg();
    is_.seekg(here);
    return end < 0 ? -1 : std::streamoff(end - here);
  }

 private:
  void read(char* p, uint64_t n) {
    is_.read(p, std::streamsize(n));
    if (!is_ || uint64_t(is_.gcount()) != n) fail("truncated file");
  }
  std::istream& is_;
  std::string what_;
};

}  // namespace core
