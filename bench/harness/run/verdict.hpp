// How a backend run ended (docs/metrics.md, Verdicts), and its name in every output file.
#pragma once

#include <optional>
#include <string_view>

namespace chainmail {

enum class Verdict {
  stable,         // none of the checks failed
  non_finite,     // a NaN or infinite entry in the frame, or the backend reported one
  max_speed,      // a ring faster than stability.max_speed
  torn_links,     // linked rings farther apart than stability.max_stretch allows
  energy_growth,  // total energy grew past stability.energy_growth
  watchdog,       // the run took longer than its wall-time limit
  interrupted,    // a signal stopped the run, or kept it from starting
};

// the name written to summary.json, the CSVs and the tables
const char* to_string(Verdict verdict);
// the verdict a name stands for (nullopt for any other text)
std::optional<Verdict> verdict_from_string(std::string_view text);

}  // namespace chainmail
