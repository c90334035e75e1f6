#include "bench/harness/suites/sweep_grid.hpp"

#include <algorithm>
#include <sstream>
#include <string_view>

#include "bench/harness/common/usage_error.hpp"

namespace chainmail {

std::vector<SweepAxis> parse_vary(const std::vector<std::string>& vary) {
  std::vector<SweepAxis> axes;
  for (const auto& v : vary) {
    const auto eq = v.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == v.size()) {
      throw UsageError("--vary '" + v + "': expected KEY=v1,v2,...");
    }
    SweepAxis axis{v.substr(0, eq), {}};
    std::stringstream values(v.substr(eq + 1));
    for (std::string value; std::getline(values, value, ',');) axis.values.push_back(value);
    axes.push_back(axis);
  }
  if (axes.empty()) throw UsageError("--vary: at least one KEY=v1,v2,... is needed");
  return axes;
}

namespace {

// in a --vary key: each backend's own name
constexpr std::string_view kBackendPlaceholder = "{backend}";

// the point at one index per axis, for one backend
SweepPoint grid_point(const std::vector<SweepAxis>& axes, const std::vector<size_t>& index,
                      const std::string& backend) {
  SweepPoint p{backend, {}, {}};
  for (size_t a = 0; a < axes.size(); ++a) {
    std::string key = axes[a].key;
    const auto placeholder = key.find(kBackendPlaceholder);
    if (placeholder != std::string::npos)
      key.replace(placeholder, kBackendPlaceholder.size(), backend);
    const std::string& value = axes[a].values[index[a]];
    // another backend's knob does not change this backend's run
    const bool other =
        key.rfind("backends.", 0) == 0 && key.rfind("backends." + backend + ".", 0) != 0;
    p.values.push_back(other ? "" : value);
    if (!other) p.sets.push_back(key + "=" + value);
  }
  return p;
}

}  // namespace

std::vector<SweepPoint> sweep_grid(const std::vector<SweepAxis>& axes,
                                   const std::vector<std::string>& backends) {
  std::vector<SweepPoint> points;
  for (const auto& axis : axes) {
    if (axis.values.empty()) return points;  // an empty axis leaves no point
  }
  for (const auto& backend : backends) {
    std::vector<size_t> index(axes.size(), 0);
    std::vector<std::vector<std::string>> seen;
    while (true) {
      SweepPoint p = grid_point(axes, index, backend);
      if (std::find(seen.begin(), seen.end(), p.sets) == seen.end()) {
        seen.push_back(p.sets);
        points.push_back(p);
      }
      // the next index, the first axis fastest
      size_t a = 0;
      while (a < axes.size() && ++index[a] == axes[a].values.size()) index[a++] = 0;
      if (a == axes.size()) break;
    }
  }
  return points;
}

}  // namespace chainmail
