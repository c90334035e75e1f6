// The output could not be written (disk full, read-only, removed underneath): exit status 4, one
// line with the file and the operating system's reason. Not a bug, not bad input.
#pragma once

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace chainmail {

inline constexpr int kExitOutput = 4;

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "cannot write PATH: REASON" for the errno of the failed call (0: the stream gave no reason)
[[noreturn]] inline void throw_write_error(const std::string& path, int error) {
  throw OutputError("cannot write " + path + ": " +
                    (error != 0 ? std::strerror(error) : "the write failed"));
}

// whether a file system error is the destination refusing what is written (as opposed to a bug)
inline bool is_output_failure(const std::error_code& code) {
  if (code.category() != std::generic_category() && code.category() != std::system_category())
    return false;
  switch (code.value()) {
    case ENOSPC:
    case EDQUOT:
    case EROFS:
    case EIO:
    case EFBIG:
    case EACCES:
    case EPERM:
    case ENOENT:
    case ENOTDIR:
      return true;
    default:
      return false;
  }
}

}  // namespace chainmail
