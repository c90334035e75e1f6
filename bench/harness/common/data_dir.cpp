#include "bench/harness/common/data_dir.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "bench/harness/common/usage_error.hpp"

// the source tree and the install's data folder relative to its bin/ folder, from
// bench/CMakeLists.txt
#ifndef CHAINMAIL_SOURCE_DIR
#define CHAINMAIL_SOURCE_DIR ""
#endif
#ifndef CHAINMAIL_DATA_FROM_BIN
#define CHAINMAIL_DATA_FROM_BIN "../share/chainmail"
#endif

namespace chainmail {
namespace {

namespace fs = std::filesystem;

bool is_dir(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(path, error);
}

// the folder of the running binary ("" when /proc cannot tell)
fs::path executable_dir() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  return error ? fs::path() : exe.parent_path();
}

const std::string& require(const DataDir& dir) {
  if (dir.root.empty()) {
    throw UsageError(
        "no data folder (bench scenes, shaders, plot script) beside this binary or in the "
        "source tree it was built from: set CHAINMAIL_DATA_DIR to <prefix>/share/chainmail or "
        "to a chainmail source tree");
  }
  return dir.root;
}

}  // namespace

std::string DataDir::scenes() const {
  return require(*this) + (source_tree ? "/bench/scenes" : "/scenes");
}

std::string DataDir::shaders() const {
  return require(*this) + "/shaders";
}

std::string DataDir::plot_script(const std::string& name) const {
  return require(*this) + (source_tree ? "/bench/" : "/") + name;
}

DataDir data_dir_at(const std::string& root) {
  return {root, is_dir(fs::path(root) / "bench" / "scenes")};
}

DataDir find_data_dir(const char* env, const std::string& installed, const std::string& source) {
  if (env && *env) return data_dir_at(env);
  if (!installed.empty() && is_dir(fs::path(installed) / "scenes")) return {installed, false};
  if (!source.empty() && is_dir(fs::path(source) / "bench" / "scenes")) return {source, true};
  return {};
}

const DataDir& data_dir() {
  static const DataDir dir = [] {
    const fs::path bin = executable_dir();
    const std::string installed =
        bin.empty() ? std::string() : (bin / CHAINMAIL_DATA_FROM_BIN).lexically_normal().string();
    return find_data_dir(std::getenv("CHAINMAIL_DATA_DIR"), installed, CHAINMAIL_SOURCE_DIR);
  }();
  return dir;
}

std::string render_shader_dir() {
  if (const fs::path bin = executable_dir(); !bin.empty() && is_dir(bin / "shaders"))
    return (bin / "shaders").string();
  if (const char* env = std::getenv("CHAINMAIL_SHADER_DIR"); env && *env && is_dir(env)) return env;
  if (const DataDir& dir = data_dir(); !dir.root.empty() && is_dir(dir.shaders()))
    return dir.shaders();
  return "";
}

std::string report_page_dir() {
  if (const fs::path bin = executable_dir(); !bin.empty() && is_dir(bin / "report"))
    return (bin / "report").string();
  if (const DataDir& dir = data_dir(); !dir.root.empty() && is_dir(dir.root + "/report"))
    return dir.root + "/report";
  return "";
}

}  // namespace chainmail
