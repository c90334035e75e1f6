// What built this binary, for summary.json, manifests and `chainmail --version`.
#pragma once

#include <string>

namespace chainmail {

// "0.2.0"
std::string chainmail_version();
// the source commit at configure time ("unknown" outside a git checkout)
std::string chainmail_commit();
// "g++ 12.2.0"
std::string chainmail_compiler();
// the CMake build type: "Release", "Debug", ...
std::string chainmail_build_type();
// "g++ 12.2.0, Release"
std::string chainmail_build();

}  // namespace chainmail
