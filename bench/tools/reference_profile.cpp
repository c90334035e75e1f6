// What the rigid references' own settings buy: bench scenes (at the bench's sizes, from the bench
// plan) through Bullet and ODE at their default knobs, then with one change at a time (fewer
// solver iterations or internal substeps, a longer step, fewer capsules per torus, fewer contacts
// per pair), as CSV on stdout. Each row gives the cost (ms per step, wall seconds per simulated
// second, speed-up over the default) and the accuracy cost: drape_rms of the changed run against
// the default run, at the end and the largest over the samples, with the capsule compound's
// surface error. A change of units by a thousandth changes nothing but rounding: its drape_rms is
// the floor below which a change's drape_rms is the chaos of a sheet of contacts, not an error.
// One thread, one run each. scripts/reference_profile.sh writes results/references/ from it.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "backends/capsule_torus.hpp"
#include "bench/harness/run/run.hpp"
#include "bench/harness/suites/bench_suite.hpp"
#include "core/metrics.hpp"
#include "scene_file/scene_file.hpp"

namespace {

using namespace chainmail;

// one configuration: knob overrides on the backend (empty: its defaults)
struct Change {
  std::string label;
  std::vector<std::string> sets;  // "knob=value"
};

std::vector<Change> changes_for(const std::string& backend) {
  if (backend == "bullet") {
    return {{"default", {}},
            {"length_scale 1001 (noise floor)", {"length_scale=1001"}},
            {"substeps 1", {"substeps=1"}},
            {"solver_iterations 10", {"solver_iterations=10"}},
            {"solver_iterations 10; substeps 1", {"solver_iterations=10", "substeps=1"}},
            {"dt 0.002; substeps 1", {"dt=0.002", "substeps=1"}},
            {"pieces 20", {"pieces=20"}},
            {"pieces 16", {"pieces=16"}}};
  }
  return {{"default", {}},
          {"length_scale 1001 (noise floor)", {"length_scale=1001"}},
          {"substeps 1", {"substeps=1"}},
          {"iterations 10", {"iterations=10"}},
          {"iterations 10; substeps 1", {"iterations=10", "substeps=1"}},
          {"dt 0.002; substeps 1", {"dt=0.002", "substeps=1"}},
          {"pieces 20", {"pieces=20"}},
          {"pieces 16", {"pieces=16"}},
          {"max_contacts 1", {"max_contacts=1"}}};
}

struct Outcome {
  BackendRun run;
  RingGeometry ring;              // the scene's, for the capsule fit's surface error
  std::vector<RingFrame> frames;  // every sample
};

Outcome run_once(const std::string& scene_file, const std::vector<std::string>& scene_sets,
                 const std::string& backend, const Change& change) {
  std::vector<std::string> sets = scene_sets;
  for (const auto& s : change.sets) sets.push_back("backends." + backend + "." + s);
  const Scene scene = load_scene_file(scene_file, sets);
  const Weave weave = make_weave(scene.weave, scene.ring);
  RunOptions options;
  options.progress = false;
  options.reference = kNoReference;
  options.threads = 1;
  Outcome out;
  out.ring = scene.ring;
  out.run = run_backend(scene, weave, backend, options,
                        [&](const RingFrame& f, Sample&) { out.frames.push_back(f); });
  return out;
}

// drape_rms against the default run, sample by sample (both sample at the scene's interval)
void drape_against(const Outcome& changed, const Outcome& base, double& final_m, double& worst_m) {
  final_m = worst_m = -1.0;
  const std::size_t count = std::min(changed.frames.size(), base.frames.size());
  for (std::size_t k = 0; k < count; ++k) {
    const double d = drape_rms(changed.frames[k], base.frames[k]);
    worst_m = std::max(worst_m, d);
    if (k + 1 == count) final_m = d;
  }
}

int usage() {
  std::fprintf(stderr,
               "chainmail_reference_profile: usage: chainmail_reference_profile SCENE_DIR "
               "[--duration S] [--backends bullet,ode] [--scenes curtain,sphere_drape]\n");
  return 2;
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::size_t from = 0;
  while (from <= list.size()) {
    const std::size_t comma = std::min(list.find(',', from), list.size());
    if (comma > from) out.push_back(list.substr(from, comma - from));
    from = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string scene_dir = argv[1];
  std::string duration;
  std::vector<std::string> backends = {"bullet", "ode"};
  std::vector<std::string> scenes = {"curtain", "sphere_drape"};
  for (int k = 2; k < argc; k += 2) {
    if (k + 1 >= argc) return usage();
    const std::string flag = argv[k], value = argv[k + 1];
    if (flag == "--duration")
      duration = value;
    else if (flag == "--backends")
      backends = split(value);
    else if (flag == "--scenes")
      scenes = split(value);
    else
      return usage();
  }
  for (const auto& b : backends) {
    if (b != "bullet" && b != "ode") return usage();
    if (!backend_built(b)) {
      std::fprintf(stderr, "chainmail_reference_profile: %s is not built into this binary\n",
                   b.c_str());
      return 2;
    }
  }
  try {
    std::printf(
        "scene,rings,backend,change,dt_s,ms_per_step,wall_per_sim_s,speedup,"
        "drape_rms_final_mm,drape_rms_max_mm,surface_error_over_a,max_stretch,"
        "broken_links,verdict\n");
    for (const auto& name : scenes) {
      // the bench's overrides of that scene (its size, duration, colliders)
      const auto& plan = bench_plan().scenes;
      const auto step = std::find_if(plan.begin(), plan.end(),
                                     [&](const BenchStep& b) { return b.file == name + ".json"; });
      if (step == plan.end()) {
        std::fprintf(stderr, "chainmail_reference_profile: %s is not a bench scene\n",
                     name.c_str());
        return 2;
      }
      const std::string file = scene_dir + "/" + step->file;
      std::vector<std::string> sets = step->full;
      if (!duration.empty()) sets.push_back("duration=" + duration);
      for (const auto& backend : backends) {
        Outcome base;
        for (const Change& change : changes_for(backend)) {
          std::fprintf(stderr, "reference profile: %s %s %s\n", name.c_str(), backend.c_str(),
                       change.label.c_str());
          Outcome out = run_once(file, sets, backend, change);
          if (change.sets.empty()) base = out;
          double final_m = 0.0, worst_m = 0.0;
          drape_against(out, base, final_m, worst_m);
          const int pieces = static_cast<int>(out.run.knobs.at("pieces"));
          const CapsuleTorus fit =
              capsule_torus(out.ring.wire_radius, out.ring.centre_radius, pieces);
          const double base_wall = base.run.wall_s / (base.run.steps * base.run.dt);
          const double wall = out.run.wall_s / (out.run.steps * out.run.dt);
          const Metrics& m = out.run.final_metrics();
          std::printf("%s,%d,%s,%s,%g,%.4g,%.4g,%.3g,%.4g,%.4g,%.4f,%.4f,%d,%s\n", name.c_str(),
                      out.frames.empty() ? 0 : out.frames.back().size(), backend.c_str(),
                      change.label.c_str(), out.run.dt, out.run.ms_per_step(), wall,
                      base_wall / wall, 1e3 * final_m, 1e3 * worst_m,
                      fit.surface_error / out.ring.wire_radius, out.run.peak_stretch,
                      static_cast<int>(m.broken_links), to_string(out.run.verdict));
          std::fflush(stdout);
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainmail_reference_profile: %s\n", e.what());
    return 2;
  }
  return 0;
}
