// What the fuzz targets share: the input cut into parts at NUL bytes, and files to hand the
// readers (they take paths), in a folder of the process's own under the temporary folder.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace chainmail::fuzz {

// the input's parts between NUL bytes (a scene file holds none: the rest are extra inputs)
inline std::vector<std::string> parts(const std::uint8_t* data, std::size_t size,
                                      std::size_t most) {
  std::vector<std::string> out(1);
  for (std::size_t k = 0; k < size; ++k) {
    if (data[k] == 0 && out.size() < most) {
      out.emplace_back();
    } else {
      out.back().push_back(static_cast<char>(data[k]));
    }
  }
  return out;
}

// a folder of this process's own, emptied at each call
inline std::string scratch() {
  static const std::filesystem::path folder = [] {
    const char* shm = "/dev/shm";  // memory, where there is one: no disk writes per input
    const std::filesystem::path base =
        std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
    return base / ("chainmail-fuzz-" + std::to_string(::getpid()));
  }();
  std::error_code ignored;
  std::filesystem::remove_all(folder, ignored);
  std::filesystem::create_directories(folder);
  return folder.string();
}

inline void write(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace chainmail::fuzz
