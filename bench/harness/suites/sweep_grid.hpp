// A sweep's grid: the --vary axes and the points they span, one backend's run each.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

// one --vary axis
struct SweepAxis {
  std::string key;  // as given: "{backend}" stands for each backend
  std::vector<std::string> values;
};

// one point of the grid: one backend's run at one value of each axis
struct SweepPoint {
  std::string backend;
  std::vector<std::string> values;  // one per axis; "" where the axis is another backend's knob
  std::vector<std::string> sets;    // the KEY=VALUE overrides the point adds to the scene
};

// --vary texts (KEY=v1,v2,...) to axes; throws UsageError for a text that is not of that form,
// and when there is none
std::vector<SweepAxis> parse_vary(const std::vector<std::string>& vary);

// every point of the grid: backend by backend in the order given, the first axis varying
// fastest. A key under `backends.` that names another backend does not change this backend's
// run: its value is left out of the point, and the points it would repeat are dropped.
std::vector<SweepPoint> sweep_grid(const std::vector<SweepAxis>& axes,
                                   const std::vector<std::string>& backends);

}  // namespace chainmail
