// Up-front estimates of what a run will cost, from the scene alone, and the budget that refuses
// runs too large for the machine before anything is allocated or simulated.
#pragma once

#include <string>
#include <vector>

#include "core/scene.hpp"

namespace chainmail {

struct Budget {
  double max_memory_gb = 8.0;   // peak resident memory of the largest backend
  double max_hours = 2.0;       // estimated wall time of every run together
  double max_output_gb = 20.0;  // frame files and streams written
};

struct Estimate {
  long long rings = 0;
  double memory_bytes = 0.0;  // the largest backend's
  double wall_seconds = 0.0;  // every backend in turn (and the reference run when it is run)
  double output_bytes = 0.0;
  std::string largest;  // backend needing the most memory
  std::string slowest;  // backend taking the longest
  long long slowest_steps = 0;
};

// number of rings a scene's weave has, without building it
long long ring_count(const Scene& scene);
// steps one backend takes for the scene at its dt
long long step_count(const Scene& scene, const std::string& backend);
// wall seconds one backend needs for the scene (rough: its per-ring-step cost)
double estimate_seconds(const Scene& scene, const std::string& backend);

// `backends` run in turn, `extra_runs` more (a reference run) are added to the wall time;
// `frame_bytes_per_ring_sample`: what is written per ring and sample (0 when nothing)
Estimate estimate_run(const Scene& scene, const std::vector<std::string>& backends,
                      double frame_bytes_per_ring_sample);

// throws SceneError naming the key that makes the run too large, with the estimate and the flag
// that raises the budget
void check_budget(const Scene& scene, const Estimate& estimate, const Budget& budget);

// "12 s", "4.2 min", "3.1 h"
std::string human_duration(double seconds);

}  // namespace chainmail
