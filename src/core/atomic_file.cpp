#include "core/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace core {

std::string write_error_text(const std::string& path, const std::string& detail, int err) {
  std::string s = "writing " + path + " failed: " + detail;
  if (err) s += std::string(" (") + std::strerror(err) + ")";
  if (err == EFBIG) s += ": a file size limit (ulimit -f)?";
  else if (!err) s += ": is the disk full?";
  return s;
}

std::string write_file_atomically(const std::string& path, const std::string& bytes) {
  const std::string tmp = path + ".tmp";
  errno = 0;
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return write_error_text(tmp, "cannot create it", errno);
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
  const int err = errno;
  if (std::fclose(f) != 0 || !written) {
    const int e = written ? errno : err;
    std::remove(tmp.c_str());
    return write_error_text(path, "not all of it was written", e);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    return write_error_text(path, "cannot rename " + tmp + " to it", e);
  }
  return "";
}

}  // namespace core
