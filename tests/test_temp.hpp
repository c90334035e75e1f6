// The folder tests write their files under: one per test process, so that two test runs at once
// (two builds' suites, or two checkouts on one machine) never share or remove each other's files.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace chainmail {

inline const std::filesystem::path& test_temp_root() {
  // removed with everything left in it when the process ends
  struct Root {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("chainmail_tests_" + std::to_string(::getpid()));
    Root() { std::filesystem::create_directories(path); }
    ~Root() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const Root root;
  return root.path;
}

}  // namespace chainmail
