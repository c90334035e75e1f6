// The `chainmail` subcommands, callable from tests without a process.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

// exit statuses (DESIGN.md): 0 ok, 1 a simulation reported unstable, 2 bad input
inline constexpr int kExitOk = 0;
inline constexpr int kExitUnstable = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitInternal = 3;

struct RunCommand {
  std::string scene_file;
  std::vector<std::string> backends;  // empty: the scene's own list
  std::string out_dir;                // empty: results/<scene name>
  bool frames = false;
  bool render = false;
  std::string shader;    // cloth shader for --render
  std::string material;  // ring material for --render (empty: steel)
  std::vector<std::string> overrides;
  bool progress = true;
  std::string cache_dir = "results/.cache";
};
int run_command(const RunCommand& command);

}  // namespace chainmail
