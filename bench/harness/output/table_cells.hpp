// Cells that several Markdown tables share (a run's table.md, the bench's timing and metrics
// tables, the stability table), so that one quantity reads the same in each of them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bench/harness/run/run.hpp"

namespace chainmail {

// yes / no, or "-" when not decided
const char* yes_no_cell(const std::optional<bool>& value);

// a depth in wire radii a, 3 significant digits
std::string wire_radii_cell(double depth_m, double wire_radius);

// wall ms per simulated second of the run of `backend` among `runs` (0 when it did not run)
double backend_cost(const std::vector<BackendRun>& runs, const std::string& backend);
// ... of the `plausible` run
double plausible_cost(const std::vector<BackendRun>& runs);
// a run's cost per simulated second relative to another's (`base`, wall ms per simulated second),
// NaN when unknown
double relative_cost(const BackendRun& run, double base);
// ... as a cell: "1.5x", "-" when unknown
std::string relative_cost_cell(const BackendRun& run, double base);
std::string cost_vs_plausible_cell(const BackendRun& run, double plausible_cost);
// dt (s) | ms/step | real-time factor | cost vs plausible
std::string timing_cells(const BackendRun& run, double plausible_cost);

// the final metrics, ten cells: max_stretch | mean_stretch | penetrating_linked |
// depth max/mean linked (a) | penetrating_other | depth max/mean other (a) | broken_links |
// false_links | drape_rms (mm) | drape_coefficient
std::string final_metric_cells(const Metrics& m, double wire_radius);
// the same ten cells for a run that never took a sample
std::string missing_metric_cells();
// a chain's sag error against the catenary in percent, "-" when absent
std::string catenary_cell(const std::optional<double>& error);

}  // namespace chainmail
