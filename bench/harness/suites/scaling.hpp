// The bench's scaling table: the curtain (self-contact on, default dt) at growing sizes, the
// plausible model on 1 and 2 threads (median of a few runs each), the other backends (on 1 and 2
// threads where they step on several) up to the size their estimated cost fits the budget, the
// median of a few runs where they are cheap, and each one's cost relative to ODE's. Cost per ring
// per step should stay flat (O(n)), and the final hash must not depend on the thread count.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

struct ScalingPlan {
  std::vector<int> sides;         // rings a side
  double duration = 0.4;          // s simulated per run
  int repeats = 3;                // runs per cell of the cheap backends (the median)
  int plausible_repeats = 5;      // ... and of plausible (its 2-thread times swing the most)
  std::vector<int> threads;       // thread counts of the backends that step on several
  double budget_s = 60.0;         // other backends: sizes whose estimated run fits this, wall s
  double repeat_budget_s = 12.0;  // ... and `repeats` runs where it fits this (one otherwise)
};

// 16, 32, 64, 128, 256 a side up to max_side (quick: 4 and 8, short runs)
ScalingPlan scaling_plan(bool quick, int max_side);

// runs the plan on `scenes`/curtain.json for the given backends ("all" or names); writes
// `out`/scaling.csv and scaling.png and returns the table in markdown (no heading)
std::string run_scaling(const ScalingPlan& plan, const std::string& scenes,
                        const std::vector<std::string>& backends, const std::string& out,
                        bool progress);

}  // namespace chainmail
