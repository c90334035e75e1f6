// The `chainmail` subcommands, callable from tests without a process.
#pragma once

#include <string>
#include <vector>

#include "bench/harness/run/budget.hpp"

namespace chainmail {

// exit statuses: 0 ok, 1 a simulation reported unstable, 2 bad input, 3 internal error,
// 130 interrupted (what finished is written)
inline constexpr int kExitOk = 0;
inline constexpr int kExitUnstable = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitInternal = 3;
inline constexpr int kExitInterrupted = 130;

// --cache none: no reference-run cache
inline constexpr const char* kNoCache = "none";

// the reference-run cache: $CHAINMAIL_CACHE_DIR, else $XDG_CACHE_HOME/chainmail, else
// ~/.cache/chainmail ("" when none of them can be named)
std::string default_cache_dir();
// "none" -> "", "" -> default_cache_dir(), else as given
std::string resolve_cache_dir(const std::string& flag);

struct RunCommand {
  std::string scene_file;
  std::vector<std::string> backends;  // empty: the scene's own list
  std::string out_dir;                // empty: results/<scene name>/run
  bool force = false;                 // replace a foreign empty folder at out_dir
  bool frames = false;
  bool render = false;
  bool report = false;    // index.html and report/ (bench/harness/report/report.hpp)
  std::string shader;     // cloth shader for --render
  std::string material;   // ring material for --render (empty: steel)
  std::string reference;  // "" = the scene's, "none" = no reference run
  std::vector<std::string> overrides;
  bool progress = true;
  int threads = 0;        // threads each backend steps on; 0: every hardware thread
  std::string cache_dir;  // "" = default_cache_dir(), "none" = no cache
  Budget budget;
  // --export: gltf and/or npz, every backend's frames into export/<backend>.glb|.npz
  std::vector<std::string> exports;
};
int run_command(const RunCommand& command);

}  // namespace chainmail
