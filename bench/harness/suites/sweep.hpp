// Sweeps: error against run time, one independent `chainmail run` per point of a grid of knob
// values, every point measured against one reference run.
#pragma once

#include <vector>

#include "bench/harness/suites/sweep_command.hpp"
#include "bench/harness/suites/sweep_grid.hpp"

namespace chainmail {

// threads each point steps on: --threads, else the hardware threads divided among the jobs
int sweep_threads(const SweepCommand& command);
int sweep_command(const SweepCommand& command);

// the dt of the reference run that every point (and a plain run) is measured against: the
// scene's reference_dt when it gives one (> 0), else the finest of the reference backend's dt in
// the scene and the dts the sweep runs that backend at
double reference_run_dt(double scene_reference_dt, double scene_dt,
                        const std::vector<double>& swept_dts);

}  // namespace chainmail
