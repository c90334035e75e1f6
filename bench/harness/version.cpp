#include "bench/harness/version.hpp"

#ifndef CHAINMAIL_VERSION
#define CHAINMAIL_VERSION "unknown"
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

std::string chainmail_build() {
#if defined(__clang__)
  const std::string compiler = "clang " __clang_version__;
#elif defined(__GNUC__)
  const std::string compiler = "g++ " __VERSION__;
#else
  const std::string compiler = "unknown compiler";
#endif
  return compiler + ", " + CHAINMAIL_BUILD_TYPE;
}

}  // namespace chainmail
