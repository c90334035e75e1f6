#include "bench/harness/report/report.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <set>

#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/report/report_data.hpp"
#include "scene_file/scene_file_text.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPage = "index.html";
constexpr const char* kAssets = "report";

bool page_file(const std::string& relative) {
  return relative == kPage || relative.rfind(std::string(kAssets) + "/", 0) == 0;
}

// the page's static files (index.html, scripts, styles, three.js) into `staging`: index.html at
// its top, the rest under report/
void copy_page(const std::string& assets, const fs::path& staging, bool frames,
               std::vector<std::string>& written) {
  for (const auto& entry : fs::directory_iterator(assets)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    if (name == "three.min.js" && !frames) continue;  // 0.85 MB a page without 3D never loads
    const std::string relative = name == kPage ? name : std::string(kAssets) + "/" + name;
    fs::copy_file(entry.path(), staging / relative, fs::copy_options::overwrite_existing);
    written.push_back(relative);
  }
}

void write_frames(const ReportInput& input, const fs::path& staging,
                  std::vector<std::string>& written) {
  for (const ReportFrames& frames : input.frames) {
    for (std::size_t k = 0; k < frames.count; ++k) {
      char name[48];
      std::snprintf(name, sizeof name, "/%05zu.js", k);
      const std::string relative = std::string(kAssets) + "/frames/" + frames.key + name;
      write_file_atomic((staging / relative).string(), frame_script(frames, k));
      written.push_back(relative);
    }
  }
}

// the staged page takes the place of the folder's old one (if any)
void swap_in(const fs::path& staging, const fs::path& folder) {
  fs::remove_all(folder / kAssets);
  fs::rename(staging / kAssets, folder / kAssets);
  fs::rename(staging / kPage, folder / kPage);
}

}  // namespace

std::vector<std::string> write_report(const std::string& folder, const std::string& command) {
  const std::string assets = report_page_dir();
  if (assets.empty())
    throw UsageError(
        "report: the page's files (report/) are neither beside this binary nor in "
        "the data folder (set CHAINMAIL_DATA_DIR)");
  const ReportInput input = read_report_input(folder, command);  // all checks, nothing written

  const fs::path staging = fs::path(folder) / (".report.partial-" + std::to_string(::getpid()));
  std::vector<std::string> written;
  try {
    fs::remove_all(staging);
    fs::create_directories(staging / kAssets);
    copy_page(assets, staging, !input.frames.empty(), written);
    write_file_atomic(
        (staging / kAssets / "data.js").string(),
        "window.CHAINMAIL_REPORT = " +
            input.data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + ";\n");
    written.push_back(std::string(kAssets) + "/data.js");
    write_frames(input, staging, written);
    swap_in(staging, folder);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
  fs::remove_all(staging);
  return written;
}

void write_report_beside(const std::string& folder, const std::string& command) {
  try {
    write_report(folder, command);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainmail: no report page: %s\n", e.what());
  }
}

int report_command(const std::string& folder) {
  std::string command;
  std::set<std::string> files;
  if (!fs::is_directory(folder) || !read_manifest(folder, command, files))
    throw UsageError(shown(folder) + ": not a folder chainmail wrote (no " + kManifestName + ")");
  if (command != "run" && command != "sweep" && command != "stability" && command != "bench")
    throw UsageError(shown(folder) + ": written by chainmail " + command +
                     "; report reads run, sweep, stability and bench folders");
  const std::vector<std::string> written = write_report(folder, command);
  // the manifest lists the page too, so that the command that made the folder may replace it
  std::set<std::string> listed;
  for (const std::string& file : files) {
    if (!page_file(file)) listed.insert(file);
  }
  listed.insert(written.begin(), written.end());
  write_manifest(folder, command, {listed.begin(), listed.end()});
  std::fprintf(stderr, "wrote %s/%s\n", folder.c_str(), kPage);
  return 0;
}

}  // namespace chainmail
