#pragma once
// Whole-file writes: through PATH.tmp renamed into place, so a reader (or a resumed run) never sees half a file and an
// existing file is replaced only by a whole one. ROS-free; used for summaries, trajectories and checkpoints.
#include <string>

namespace core {

// "writing PATH failed: DETAIL (errno's text)", naming a file size limit (EFBIG) or, with no errno, a full disk.
std::string write_error_text(const std::string& path, const std::string& detail, int err);

// Writes `bytes` to `path` through `path`.tmp and a rename. Returns "" or write_error_text's message; the temporary
// file is removed on failure.
std::string write_file_atomically(const std::string& path, const std::string& bytes);

}  // namespace core
