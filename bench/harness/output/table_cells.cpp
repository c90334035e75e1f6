#include "bench/harness/output/table_cells.hpp"

#include <cmath>
#include <sstream>

#include "bench/harness/output/number_format.hpp"

namespace chainmail {

const char* yes_no_cell(const std::optional<bool>& value) {
  return value ? (*value ? "yes" : "no") : "-";
}

std::string wire_radii_cell(double depth_m, double wire_radius) {
  return table_number(depth_m / wire_radius, 3);
}

double backend_cost(const std::vector<BackendRun>& runs, const std::string& backend) {
  double cost = 0.0;
  for (const auto& r : runs) {
    if (r.name == backend && r.dt > 0) cost = r.ms_per_step() / r.dt;
  }
  return cost;
}

double plausible_cost(const std::vector<BackendRun>& runs) {
  return backend_cost(runs, "plausible");
}

double relative_cost(const BackendRun& run, double base) {
  return base > 0 && run.dt > 0 ? (run.ms_per_step() / run.dt) / base : NAN;
}

std::string relative_cost_cell(const BackendRun& run, double base) {
  const double relative = relative_cost(run, base);
  return std::isnan(relative) ? "-" : table_number(relative, 3) + "x";
}

std::string cost_vs_plausible_cell(const BackendRun& run, double plausible_cost) {
  return relative_cost_cell(run, plausible_cost);
}

std::string timing_cells(const BackendRun& run, double plausible_cost) {
  std::ostringstream out;  // dt as a stream prints it: 6 significant digits
  out << run.dt << " | " << table_number(run.ms_per_step(), 4) << " | "
      << table_number(run.realtime_factor(), 3) << " | "
      << cost_vs_plausible_cell(run, plausible_cost);
  return out.str();
}

std::string final_metric_cells(const Metrics& m, double a) {
  std::ostringstream out;
  out << table_number(m.max_stretch, 4) << " | " << table_number(m.mean_stretch, 4) << " | "
      << m.penetrating_linked << " | " << wire_radii_cell(m.penetration_max_linked, a) << " / "
      << wire_radii_cell(m.penetration_mean_linked, a) << " | " << m.penetrating_other << " | "
      << wire_radii_cell(m.penetration_max_other, a) << " / "
      << wire_radii_cell(m.penetration_mean_other, a) << " | " << m.broken_links << " | "
      << m.false_links << " | " << (m.drape_rms ? table_number(1e3 * *m.drape_rms, 3) : "-")
      << " | " << (m.drape_coefficient ? table_number(*m.drape_coefficient, 3) : "-");
  return out.str();
}

std::string missing_metric_cells() {
  return "- | - | - | - | - | - | - | - | - | -";
}

std::string catenary_cell(const std::optional<double>& error) {
  return error ? table_number(100.0 * *error, 3) + " %" : "-";
}

}  // namespace chainmail
