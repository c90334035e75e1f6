// The stability suite: stiff and extreme cases (scene files under bench/scenes/stability/), the
// verdict of each backend at its default knobs and the largest stable dt found by bisection.
#pragma once

#include <string>
#include <vector>

#include "core/scene.hpp"

namespace chainmail {

struct StabilityCommand {
  std::vector<std::string> backends;  // empty: every backend
  std::string out_dir = "results/stability";
  bool force = false;
  bool quick = false;              // tiny sizes, for tests
  double max_wall_seconds = 30.0;  // watchdog per run
  int threads = 0;                 // threads each run steps on; 0: every hardware thread
  bool progress = true;
};
int stability_command(const StabilityCommand& command);

// one case of the suite; its name and description are the scene's
struct StabilityCase {
  std::string file;                // under bench/scenes/stability/
  std::vector<std::string> only;   // restrict to these backends (empty: every backend)
  int bisection_steps = 3;         // halvings (in log space) of the searched dt range
  std::vector<std::string> quick;  // --set overrides of the quick mode (smaller, shorter)
};

// the cases in the order the tables list them
const std::vector<StabilityCase>& stability_cases();
// a case's scene, reduced in quick mode
Scene load_stability_case(const StabilityCase& c, bool quick);

}  // namespace chainmail
