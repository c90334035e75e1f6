// Sweeps: the grid of points, the reference run's dt, and a small sweep end to end.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/suites/process.hpp"
#include "bench/harness/suites/sweep.hpp"
#include "scene_file/scene_file.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using Strings = std::vector<std::string>;

std::string vary_error(const Strings& vary) {
  try {
    parse_vary(vary);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "(no error)";
}

Strings lines_of(const std::string& text) {
  Strings lines;
  std::stringstream stream(text);
  for (std::string line; std::getline(stream, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

TEST(SweepGrid, EveryCombinationBackendByBackendFirstAxisFastest) {
  const std::vector<SweepAxis> axes =
      parse_vary({"backends.{backend}.dt=0.004,0.002", "duration=1,2,3"});
  ASSERT_EQ(axes.size(), 2u);
  EXPECT_EQ(axes[0].key, "backends.{backend}.dt");
  EXPECT_EQ(axes[1].values, (Strings{"1", "2", "3"}));
  const std::vector<SweepPoint> points = sweep_grid(axes, {"plausible", "massspring"});
  ASSERT_EQ(points.size(), 2u * 2u * 3u);
  EXPECT_EQ(points[0].backend, "plausible");
  EXPECT_EQ(points[0].sets, (Strings{"backends.plausible.dt=0.004", "duration=1"}));
  EXPECT_EQ(points[1].sets, (Strings{"backends.plausible.dt=0.002", "duration=1"}));
  EXPECT_EQ(points[2].sets, (Strings{"backends.plausible.dt=0.004", "duration=2"}));
  EXPECT_EQ(points[5].values, (Strings{"0.002", "3"}));
  // "{backend}" stands for each backend in turn
  EXPECT_EQ(points[6].backend, "massspring");
  EXPECT_EQ(points[6].sets, (Strings{"backends.massspring.dt=0.004", "duration=1"}));
  EXPECT_EQ(points[11].sets, (Strings{"backends.massspring.dt=0.002", "duration=3"}));
}

TEST(SweepGrid, AnotherBackendsKnobAddsNoPoint) {
  const std::vector<SweepPoint> points = sweep_grid(
      parse_vary({"backends.{backend}.dt=0.004,0.002", "backends.plausible.iterations=2,8"}),
      {"plausible", "massspring"});
  // plausible: 2 x 2; massspring: its two dts only, plausible's knob left blank
  ASSERT_EQ(points.size(), 4u + 2u);
  EXPECT_EQ(points[3].sets,
            (Strings{"backends.plausible.dt=0.002", "backends.plausible.iterations=8"}));
  EXPECT_EQ(points[4].backend, "massspring");
  EXPECT_EQ(points[4].values, (Strings{"0.004", ""}));
  EXPECT_EQ(points[4].sets, (Strings{"backends.massspring.dt=0.004"}));
  EXPECT_EQ(points[5].sets, (Strings{"backends.massspring.dt=0.002"}));
  // a key outside backends. applies to every backend
  EXPECT_EQ(sweep_grid(parse_vary({"duration=1,2"}), {"plausible", "massspring"}).size(), 4u);
}

TEST(SweepGrid, BadVaryIsBadInputNamingTheText) {
  for (const char* text : {"dt", "=0.1,0.2", "dt="}) {
    EXPECT_EQ(vary_error({text}), "--vary '" + std::string(text) + "': expected KEY=v1,v2,...");
  }
  EXPECT_EQ(vary_error({"duration=1", "x"}), "--vary 'x': expected KEY=v1,v2,...");
  EXPECT_EQ(vary_error({}), "--vary: at least one KEY=v1,v2,... is needed");
}

TEST(ReferenceRunDt, TheScenesOwnElseTheFinestTheReferenceRunsAt) {
  EXPECT_EQ(reference_run_dt(0.0005, 0.001, {0.0001}), 0.0005);  // reference_dt decides
  EXPECT_EQ(reference_run_dt(0.0, 0.001, {}), 0.001);            // not swept: its dt in the scene
  EXPECT_EQ(reference_run_dt(0.0, 0.001, {0.004, 0.0005, 0.002}), 0.0005);  // the finest swept
  EXPECT_EQ(reference_run_dt(0.0, 0.001, {0.004, 0.002}), 0.001);  // never above the scene's
}

TEST(Sweep, PrintJobsOneLinePerPointAgainstOneReference) {
  SweepCommand sweep;
  sweep.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  sweep.vary = {"backends.{backend}.dt=0.004,0.002,0.001"};
  sweep.backends = {"plausible"};
  sweep.print_jobs = true;
  testing::internal::CaptureStdout();
  ASSERT_EQ(sweep_command(sweep), kExitOk);
  Strings lines = lines_of(testing::internal::GetCapturedStdout());
  ASSERT_EQ(lines.size(), 4u);
  // the reference job first: the points read its run from the cache instead of each running it
  EXPECT_NE(lines[0].find(" sweep "), std::string::npos) << lines[0];
  EXPECT_TRUE(lines[0].ends_with(" --reference-only")) << lines[0];
  EXPECT_NE(lines[3].find(" --set 'backends.plausible.dt=0.001' "), std::string::npos);
  lines.erase(lines.begin());
  if (!backend_built("bullet")) GTEST_SKIP() << "the scene's reference, bullet, is not built";
  // the reference (bullet) is not swept: it runs at its dt in the scene, the same for every point
  for (const auto& line : lines) {
    EXPECT_TRUE(line.ends_with(" --set 'reference_dt=0.001'")) << line;
  }
  // a sweep over the reference backend's dt measures every point against its finest
  sweep.backends = {"plausible", "bullet"};
  sweep.vary = {"backends.{backend}.dt=0.004,0.0005"};
  testing::internal::CaptureStdout();
  ASSERT_EQ(sweep_command(sweep), kExitOk);
  lines = lines_of(testing::internal::GetCapturedStdout());
  ASSERT_EQ(lines.size(), 5u);
  lines.erase(lines.begin());
  for (const auto& line : lines) {
    EXPECT_TRUE(line.ends_with(" --set 'reference_dt=0.0005'")) << line;
  }
  // a bad knob value is bad input before anything runs
  sweep.vary = {"backends.{backend}.dt=-1"};
  EXPECT_THROW(sweep_command(sweep), SceneError);
}

TEST(Sweep, RefusesToVaryTheReferenceBackendsOwnKnobs) {
  // every point against one reference run: a point that changed the reference backend's
  // iterations would make a reference run with them too and measure an error of 0 against itself
  SweepCommand sweep;
  sweep.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  sweep.overrides = {"reference=plausible"};
  sweep.vary = {"backends.plausible.iterations=2,8"};
  sweep.backends = {"plausible", "massspring"};
  sweep.print_jobs = true;
  try {
    sweep_command(sweep);
    ADD_FAILURE() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--vary backends.plausible.iterations: plausible is the "
                                         "scene's reference"),
              std::string::npos)
        << e.what();
  }
  // its dt is fine (the reference run sets its own), and so are other backends' knobs
  sweep.vary = {"backends.{backend}.dt=0.004,0.002", "backends.massspring.substeps=10,20"};
  testing::internal::CaptureStdout();
  EXPECT_EQ(sweep_command(sweep), kExitOk);
  EXPECT_EQ(lines_of(testing::internal::GetCapturedStdout()).size(), 1u + 2u + 4u);
}

TEST(Sweep, OneRowPerPointAndThePlot) {
  const fs::path out = chainmail::test_temp_root() / "chainmail_test_sweep";
  fs::remove_all(out);
  SweepCommand sweep;
  sweep.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  sweep.overrides = {"weave.rows=4", "weave.cols=4", "duration=0.04", "reference=massspring"};
  sweep.vary = {"backends.{backend}.dt=0.004,0.002", "backends.{backend}.iterations=2,8"};
  sweep.backends = {"plausible"};
  sweep.out_dir = out.string();
  sweep.jobs = 2;
  sweep.executable = CHAINMAIL_BINARY_DIR "/bench/chainmail";
  sweep.progress = false;
  sweep.cache_dir = (out.string() + "_cache");  // beside the output: inside it is not ours
  ASSERT_EQ(sweep_command(sweep), kExitOk);
  std::ifstream csv(out / "sweep.csv");
  const Strings rows = lines_of(std::string(std::istreambuf_iterator<char>(csv), {}));
  ASSERT_EQ(rows.size(), 1u + 4u);  // header + 2 x 2 points
  EXPECT_EQ(rows[0],
            "backend,backends.{backend}.dt,backends.{backend}.iterations,wall_per_sim_s,"
            "ms_per_step,error_m,catenary_error,stable,verdict");
  EXPECT_TRUE(rows[1].starts_with("plausible,0.004,2,")) << rows[1];
  EXPECT_TRUE(rows[4].starts_with("plausible,0.002,8,")) << rows[4];
  for (size_t k = 1; k < rows.size(); ++k)
    EXPECT_TRUE(rows[k].ends_with(",true,stable")) << rows[k];
  if (!plotting_python().empty()) {
    EXPECT_TRUE(fs::exists(out / "sweep.png"));
    EXPECT_GT(fs::file_size(out / "sweep.png"), 1000u);
  }
  fs::remove_all(out);
  fs::remove_all(out.string() + "_cache");
}

}  // namespace
}  // namespace chainmail
