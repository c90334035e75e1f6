#include "bench/harness/output/output_folder.hpp"

#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/harness/common/version.hpp"
#include "bench/harness/output/output_error.hpp"
#include "core/scene.hpp"

namespace chainmail {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// room left in a name for the staging suffix (".NAME.partial-PID")
constexpr std::size_t kLongestName = NAME_MAX - 32;

const char* kind_of(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a folder";
}

}  // namespace

bool read_manifest(const std::string& folder, std::string& command, std::set<std::string>& files) {
  struct stat info {};
  const fs::path path = fs::path(folder) / kManifestName;
  if (::lstat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode) || info.st_size > (64 << 20))
    return false;
  std::ifstream in(path);
  const json manifest = json::parse(in, nullptr, false);
  if (manifest.is_discarded() || !manifest.is_object() || !manifest.contains("command") ||
      !manifest["command"].is_string() || !manifest.contains("files") ||
      !manifest["files"].is_array()) {
    return false;
  }
  command = manifest["command"].get<std::string>();
  for (const auto& f : manifest["files"]) {
    if (f.is_string()) files.insert(f.get<std::string>());
  }
  return true;
}

void write_manifest(const std::string& folder, const std::string& command,
                    const std::vector<std::string>& files) {
  const json manifest = {
      {"chainmail", chainmail_version()}, {"command", command}, {"files", files}};
  const fs::path path = fs::path(folder) / kManifestName;
  errno = 0;
  std::ofstream out(path);
  out << manifest.dump(1) << "\n";
  out.flush();
  if (!out) throw_write_error(path.string(), errno);
}

namespace {

// the first entry under `folder` that its manifest does not list ("" when none)
std::string first_foreign_entry(const fs::path& folder, const std::set<std::string>& files) {
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    const fs::path relative = fs::relative(it->path(), folder);
    const fs::file_status status = it->symlink_status();
    if (fs::is_directory(status)) continue;
    if (!fs::is_regular_file(status) ||
        (relative != kManifestName && !files.count(relative.generic_string()))) {
      return relative.string();
    }
  }
  return ec ? std::string("(unreadable: ") + ec.message() + ")" : "";
}

bool is_empty_folder(const fs::path& folder) {
  std::error_code ec;
  return fs::is_empty(folder, ec) && !ec;
}

std::vector<std::string> files_under(const fs::path& folder) {
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (!entry.is_directory()) files.push_back(fs::relative(entry.path(), folder).generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// what is lexically wrong with the path, before the file system is asked ("" when nothing)
std::string lexical_refusal(const std::string& path) {
  if (path.find_first_not_of(" \t\r\n") == std::string::npos) return "an empty path";
  if (path.back() == '/') return "ends with '/': name the folder itself";
  const std::string name = fs::path(path).filename().string();
  if (name == "." || name == "..") return "names an existing folder ('.' or '..'), not a new one";
  if (path.size() >= PATH_MAX) return "is too long";
  for (const auto& part : fs::path(path)) {
    if (part.string().size() > kLongestName)
      return "has a name longer than " + std::to_string(kLongestName) + " characters";
  }
  return "";
}

// what marks a staging folder as chainmail's: the process that made it, identified beyond its pid
// (pids are reused) by its start time since boot and the boot it started in
constexpr const char* kStagingMarker = ".chainmail-staging";

std::string read_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// "PID START BOOT" for a process (START: field 22 of /proc/PID/stat, in clock ticks since boot);
// "" when it is gone
std::string process_identity(long pid) {
  const std::string stat = read_line("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t close = stat.rfind(')');  // the command name may hold spaces and ')'
  if (close == std::string::npos) return "";
  std::istringstream fields(stat.substr(close + 2));
  std::string field;
  for (int k = 3; k <= 22 && fields >> field; ++k) {
  }
  return std::to_string(pid) + " " + field + " " + read_line("/proc/sys/kernel/random/boot_id");
}

// where a pid means one process: this host and pid namespace ("HOST:pid:[INODE]"); a staging
// folder made elsewhere (another node of a cluster on a shared file system, another container)
// is never judged from here
std::string pid_space() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  std::error_code ignored;
  return std::string(host) + ":" + fs::read_symlink("/proc/self/ns/pid", ignored).string();
}

// what a staging folder's marker holds: "PID START BOOT PID_SPACE"
std::string marker_text() {
  return process_identity(::getpid()) + " " + pid_space();
}

// whether the process a marker names is gone: no such pid, or a pid now another process's
bool marker_process_gone(const std::string& marker, long pid) {
  if (marker.rfind(std::to_string(pid) + " ", 0) != 0) return false;  // not this folder's pid
  const std::size_t space = marker.rfind(' ');
  if (marker.substr(space + 1) != pid_space()) return false;
  if (::kill(static_cast<pid_t>(pid), 0) != 0) return errno == ESRCH;
  const std::string now = process_identity(pid);
  return !now.empty() && now != marker.substr(0, space);
}

// removes the staging folders of runs into `target` that were killed (kill -9, power loss):
// ".NAME.partial-PID" folders holding chainmail's marker whose process is gone
void remove_dead_staging(const fs::path& target) {
  std::string prefix = ".";  // appended: GCC 12 warns falsely on "." + name
  prefix += target.filename().string() + ".partial-";
  std::error_code ec;
  for (auto it = fs::directory_iterator(target.parent_path(), ec);
       !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0 || !it->is_directory(ec) || it->is_symlink(ec)) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      continue;
    const fs::path marker = it->path() / kStagingMarker;
    struct stat info {};
    if (::lstat(marker.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) continue;  // not ours
    if (!marker_process_gone(read_line(marker.string()), std::stol(digits))) continue;
    std::error_code ignored;
    fs::remove_all(it->path(), ignored);
  }
}

[[noreturn]] void refuse(const std::string& flag, const std::string& path, const std::string& why) {
  throw SceneError(flag + " '" + path + "': " + why);
}

// a folder that cannot be made: a file system that takes no writes (read-only, full, failing) is
// the output that could not be written (exit 4); anything else is a path to refuse (exit 2)
[[noreturn]] void cannot_create(const std::string& flag, const std::string& path,
                                const std::string& folder, int error) {
  if (error == EROFS || error == ENOSPC || error == EDQUOT || error == EIO)
    throw_write_error(folder, error);
  refuse(flag, path,
         (folder == path ? "" : "cannot create " + folder + ": ") + std::strerror(error));
}

}  // namespace

std::string replace_refusal(const std::string& path, const std::string& command, bool force) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) return "";
    return std::strerror(errno);
  }
  if (!S_ISDIR(info.st_mode)) {
    return std::string("is ") + kind_of(info.st_mode) + ", not a folder chainmail made";
  }
  std::string made_by;
  std::set<std::string> files;
  if (!read_manifest(path, made_by, files)) {
    if (is_empty_folder(path)) {
      return force ? "" : "is a folder chainmail did not make (it is empty: --force replaces it)";
    }
    return "is a folder chainmail did not make: refusing to replace it";
  }
  if (made_by != command) {
    return "holds the output of 'chainmail " + made_by + "', which 'chainmail " + command +
           "' does not replace";
  }
  const std::string foreign = first_foreign_entry(path, files);
  if (!foreign.empty()) {
    return "holds '" + foreign + "', which chainmail did not write: refusing to replace it";
  }
  return "";
}

OutputFolder OutputFolder::claim(const std::string& path, const std::string& command, bool force,
                                 const std::string& flag) {
  if (const std::string why = lexical_refusal(path); !why.empty()) {
    if (why == "an empty path") throw SceneError(flag + ": an empty path");
    refuse(flag, path, why);
  }
  if (const std::string why = replace_refusal(path, command, force); !why.empty())
    refuse(flag, path, why);

  OutputFolder folder;
  folder.path_ = path;
  folder.command_ = command;
  folder.flag_ = flag;
  folder.force_ = force;

  // missing parents are created (and removed again if nothing is committed)
  const fs::path target = fs::absolute(path).lexically_normal();
  std::vector<fs::path> missing;
  for (fs::path p = target.parent_path(); !p.empty(); p = p.parent_path()) {
    struct stat info {};
    if (::stat(p.c_str(), &info) == 0) {
      if (!S_ISDIR(info.st_mode)) refuse(flag, path, p.string() + " is not a folder");
      break;
    }
    if (errno != ENOENT) refuse(flag, path, p.string() + ": " + std::strerror(errno));
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0) {
      const int error = errno;
      // another process made it since (the points of a sweep on Slurm or GNU parallel start
      // together and share their parents): there to use, and not ours to remove
      struct stat info {};
      if (error == EEXIST && ::stat(it->c_str(), &info) == 0 && S_ISDIR(info.st_mode)) continue;
      cannot_create(flag, path, it->string(), error);  // the destructor removes what was made
    }
    folder.created_parents_.push_back(it->string());
  }

  // the staging folder beside the destination, so that commit() is a rename
  const std::string pid = std::to_string(::getpid());
  std::string staging_name = ".";  // appended, not "." + name: GCC 12 warns falsely on that
  staging_name += target.filename().string() + ".partial-" + pid;
  const fs::path staging = target.parent_path() / staging_name;
  std::error_code ignored;
  fs::remove_all(staging, ignored);  // a leftover of this very pid cannot be a user's
  remove_dead_staging(target);
  if (::mkdir(staging.c_str(), 0777) != 0) cannot_create(flag, path, path, errno);
  folder.staging_ = staging.string();
  errno = 0;
  std::ofstream marker(staging / kStagingMarker);
  marker << marker_text() << "\n";
  marker.flush();
  if (!marker) throw_write_error((staging / kStagingMarker).string(), errno);
  return folder;
}

OutputFolder::OutputFolder(OutputFolder&& other) noexcept
    : path_(std::move(other.path_)),
      staging_(std::move(other.staging_)),
      command_(std::move(other.command_)),
      flag_(std::move(other.flag_)),
      force_(other.force_),
      committed_(other.committed_),
      created_parents_(std::move(other.created_parents_)) {
  other.committed_ = true;  // the moved-from folder owns nothing
  other.staging_.clear();
  other.created_parents_.clear();
}

OutputFolder::~OutputFolder() {
  if (committed_) return;
  std::error_code ignored;
  if (!staging_.empty()) fs::remove_all(staging_, ignored);
  for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it)
    fs::remove(*it, ignored);  // only while empty: never another process's files
}

void OutputFolder::commit() {
  fs::remove(fs::path(staging_) / kStagingMarker);  // the folder is complete: no longer staging
  write_manifest(staging_, command_, files_under(staging_));

  // the destination may have changed while the command ran: ask again before replacing it
  if (const std::string why = replace_refusal(path_, command_, force_); !why.empty()) {
    committed_ = true;  // keep the results where they are
    throw SceneError(flag_ + " '" + path_ + "': " + why + " (the results are in " + staging_ + ")");
  }
  const fs::path target(path_);
  std::string old_name = ".";
  old_name += target.filename().string() + ".old-" + std::to_string(::getpid());
  const fs::path old = fs::path(staging_).parent_path() / old_name;
  const bool replacing = fs::exists(fs::symlink_status(target));
  if (replacing) fs::rename(target, old);
  fs::rename(staging_, target);
  committed_ = true;
  std::error_code ignored;
  if (replacing) fs::remove_all(old, ignored);  // checked above: only what chainmail wrote
}

}  // namespace chainmail
