#include "bench/harness/common/version.hpp"

#ifndef CHAINMAIL_VERSION
#define CHAINMAIL_VERSION "unknown"
#endif
// the commit, written at build time (cmake/commit_stamp.cmake)
#if __has_include("chainmail_commit.inc")
#include "chainmail_commit.inc"
#endif
#ifndef CHAINMAIL_COMMIT
#define CHAINMAIL_COMMIT "unknown"
#endif
#ifndef CHAINMAIL_BUILD_TYPE
#define CHAINMAIL_BUILD_TYPE "unknown"
#endif

namespace chainmail {

std::string chainmail_version() {
  return CHAINMAIL_VERSION;
}
std::string chainmail_commit() {
  return CHAINMAIL_COMMIT;
}

std::string chainmail_compiler() {
#if defined(__clang__)
  return "clang " __clang_version__;
#elif defined(__GNUC__)
  return "g++ " __VERSION__;
#else
  return "unknown compiler";
#endif
}

std::string chainmail_build_type() {
  return CHAINMAIL_BUILD_TYPE;
}

std::string chainmail_build() {
  return chainmail_compiler() + ", " + chainmail_build_type();
}

}  // namespace chainmail
