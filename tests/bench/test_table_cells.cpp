// Table cells shared by the Markdown tables: what each one prints.
#include <gtest/gtest.h>

#include <sstream>

#include "bench/harness/output/table_cells.hpp"

namespace chainmail {
namespace {

BackendRun timed(const std::string& name, double dt, long long steps, double wall_s) {
  BackendRun run;
  run.name = name;
  run.dt = dt;
  run.steps = steps;
  run.wall_s = wall_s;
  return run;
}

std::vector<std::string> cells_of(const std::string& row) {
  std::vector<std::string> cells;
  size_t start = 0;
  for (size_t bar; (bar = row.find(" | ", start)) != std::string::npos; start = bar + 3) {
    cells.push_back(row.substr(start, bar - start));
  }
  cells.push_back(row.substr(start));
  return cells;
}

TEST(TableCells, CostPerSimulatedSecondRelativeToPlausible) {
  const BackendRun plausible = timed("plausible", 0.004, 100, 0.2);  // 2 ms a 4 ms step
  const BackendRun bullet = timed("bullet", 0.001, 100, 0.1);        // 1 ms a 1 ms step
  const double cost = plausible_cost({plausible, bullet});
  EXPECT_DOUBLE_EQ(cost, 500.0);  // ms per simulated second
  EXPECT_EQ(cost_vs_plausible_cell(plausible, cost), "1x");
  EXPECT_EQ(cost_vs_plausible_cell(bullet, cost), "2x");  // half the time, a quarter of the dt
  EXPECT_EQ(timing_cells(bullet, cost), "0.001 | 1 | 1 | 2x");
  // without a plausible run there is nothing to compare with
  EXPECT_EQ(plausible_cost({bullet}), 0.0);
  EXPECT_EQ(cost_vs_plausible_cell(bullet, 0.0), "-");
}

TEST(TableCells, CostPerSimulatedSecondRelativeToAnyBackend) {
  const BackendRun ode = timed("ode", 0.001, 1000, 10.0);         // 10 ms a 1 ms step
  const BackendRun torus = timed("torus_xpbd", 0.005, 200, 1.6);  // 8 ms a 5 ms step
  const double cost = backend_cost({torus, ode}, "ode");
  EXPECT_DOUBLE_EQ(cost, 10000.0);  // ms per simulated second
  EXPECT_EQ(relative_cost_cell(torus, cost), "0.16x");
  EXPECT_EQ(relative_cost_cell(ode, cost), "1x");
  EXPECT_EQ(backend_cost({torus}, "ode"), 0.0);
  EXPECT_EQ(relative_cost_cell(torus, 0.0), "-");
}

TEST(TableCells, FlagsDepthsAndCatenary) {
  EXPECT_STREQ(yes_no_cell(true), "yes");
  EXPECT_STREQ(yes_no_cell(false), "no");
  EXPECT_STREQ(yes_no_cell(std::nullopt), "-");
  EXPECT_EQ(wire_radii_cell(0.0004, 0.0008), "0.5");
  EXPECT_EQ(catenary_cell(0.0123), "1.23 %");
  EXPECT_EQ(catenary_cell(std::nullopt), "-");
}

TEST(TableCells, TenFinalMetricCellsEitherWay) {
  Metrics m;
  m.max_stretch = 1.002;
  m.penetrating_linked = 3;
  m.penetration_max_linked = 0.0008;   // m: one wire radius below
  m.penetration_mean_linked = 0.0004;  // m
  m.broken_links = 2;
  m.drape_rms = 0.0025;  // m
  const std::vector<std::string> cells = cells_of(final_metric_cells(m, 0.0008));
  ASSERT_EQ(cells.size(), 10u);
  EXPECT_EQ(cells[0], "1.002");
  EXPECT_EQ(cells[2], "3");
  EXPECT_EQ(cells[3], "1 / 0.5");
  EXPECT_EQ(cells[5], "0 / 0");
  EXPECT_EQ(cells[6], "2");
  EXPECT_EQ(cells[8], "2.5");  // mm
  EXPECT_EQ(cells[9], "-");    // no support: no drape coefficient
  EXPECT_EQ(cells_of(missing_metric_cells()), std::vector<std::string>(10, "-"));
}

}  // namespace
}  // namespace chainmail
