// The one folder a command writes, and the rule that keeps a user's files safe: chainmail only
// ever replaces a folder it made itself, holding only files it wrote.
//
// claim() checks the destination before any simulation starts (bad paths are bad input, exit 2),
// creates missing parent folders and a staging folder beside the destination. The command writes
// into staging(); commit() lists every file in a manifest (`.chainmail-manifest.json`: command,
// version, files) and swaps the staging folder in with two renames. A folder that is not
// committed (an error, an exception) is removed, and so are the parents claim() created.
#pragma once

#include <set>
#include <string>
#include <vector>

namespace chainmail {

inline constexpr const char* kManifestName = ".chainmail-manifest.json";

class OutputFolder {
 public:
  // `command`: run, sweep, stability, bench or render (a folder is only replaced by the command
  // that made it); `force`: a foreign *empty* folder may be replaced; `flag`: how messages name
  // the path.
  // Throws SceneError (exit 2) naming the path and what is wrong with it.
  static OutputFolder claim(const std::string& path, const std::string& command, bool force,
                            const std::string& flag = "--out");

  OutputFolder(OutputFolder&& other) noexcept;
  OutputFolder& operator=(OutputFolder&&) = delete;
  ~OutputFolder();

  const std::string& path() const { return path_; }
  const std::string& staging() const { return staging_; }
  // manifest, then the staging folder takes the destination's place
  void commit();

 private:
  OutputFolder() = default;
  std::string path_, staging_, command_, flag_;
  bool force_ = false;
  bool committed_ = false;
  std::vector<std::string> created_parents_;  // deepest last, removed when nothing is committed
};

// the files a folder's manifest lists, and the command that made it; false without a manifest
bool read_manifest(const std::string& folder, std::string& command, std::set<std::string>& files);
// the manifest of `folder`: what `command` made there, the files (relative, sorted) it wrote
void write_manifest(const std::string& folder, const std::string& command,
                    const std::vector<std::string>& files);

// why `path` may not be replaced by `command` ("" when it may: absent, or a folder that
// `command` made holding only the files its manifest lists, or an empty folder under `force`)
std::string replace_refusal(const std::string& path, const std::string& command, bool force);

}  // namespace chainmail
