#include "bench/harness/run/verdict.hpp"

#include <array>

namespace chainmail {

namespace {

constexpr std::array kVerdicts = {Verdict::stable,     Verdict::non_finite,    Verdict::max_speed,
                                  Verdict::torn_links, Verdict::energy_growth, Verdict::watchdog,
                                  Verdict::interrupted};

}  // namespace

const char* to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::stable:
      return "stable";
    case Verdict::non_finite:
      return "non_finite";
    case Verdict::max_speed:
      return "max_speed";
    case Verdict::torn_links:
      return "torn_links";
    case Verdict::energy_growth:
      return "energy_growth";
    case Verdict::watchdog:
      return "watchdog";
    case Verdict::interrupted:
      return "interrupted";
  }
  return "unknown";
}

std::optional<Verdict> verdict_from_string(std::string_view text) {
  for (Verdict verdict : kVerdicts) {
    if (text == to_string(verdict)) return verdict;
  }
  return std::nullopt;
}

}  // namespace chainmail
