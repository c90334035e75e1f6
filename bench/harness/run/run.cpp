// One backend through one scene: the step loop, its samples and the verdict checks on them.
#include "bench/harness/run/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>

#include "backends/open_backend.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/run/budget.hpp"

namespace chainmail {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// potential energy in the scene's gravity, relative to the origin
double potential_energy(const RingFrame& frame, const Scene& scene,
                        const std::vector<double>& mass) {
  double potential = 0.0;
  for (int i = 0; i < frame.size(); ++i)
    potential -= mass[i] * scene.gravity.dot(frame.position.col(i));
  return potential;
}

// energy scale of the scene: every ring falling across the rest layout's extent once
double energy_scale(const Scene& scene, const Weave& weave) {
  const Vec3 extent =
      weave.rest_position.rowwise().maxCoeff() - weave.rest_position.rowwise().minCoeff();
  const double size = std::max(extent.norm(), scene.ring.centre_radius);
  double total = 0.0;
  for (double m : ring_masses(scene, weave)) total += m;
  const double speed = scene.initial_velocity.norm();
  return total * (std::max(scene.gravity.norm(), 1.0) * size + 0.5 * speed * speed);
}

// the verdict of one sample's metrics (nullopt while stable), checked in the order of
// docs/metrics.md
std::optional<Verdict> verdict_of(const Metrics& m, const Scene& scene, double energy_growth,
                                  double scale) {
  if (m.non_finite > 0) return Verdict::non_finite;
  if (m.max_speed > scene.stability.max_speed) return Verdict::max_speed;
  // torn: farther apart than linked rings can be. (broken_links, the linking test on the emitted
  // orientations, is reported but not a verdict: a particle model's orientations are derived, so
  // its rings can look unlinked while the model holds them together.)
  if (scene.stability.links_must_hold && m.max_stretch > scene.stability.max_stretch)
    return Verdict::torn_links;
  if (energy_growth > (scene.stability.energy_growth - 1.0) * scale) return Verdict::energy_growth;
  return std::nullopt;
}

// one progress line: the first after a second, then every second on a terminal, every ten in a log
class Progress {
 public:
  Progress(bool enabled, std::string name, double duration)
      : enabled_(enabled), name_(std::move(name)), duration_(duration), terminal_(::isatty(2)) {}
  void update(double t, double ms_per_step) {
    if (!enabled_ || seconds_since(last_) <= (terminal_ || !shown_ ? 1.0 : 10.0)) return;
    last_ = Clock::now();
    shown_ = true;
    const double elapsed = seconds_since(started_);
    const double eta = t > 0.0 ? elapsed * (duration_ - t) / t : 0.0;
    std::fprintf(stderr, "%s  %-10s t = %7.3f / %.3f s  %8.3f ms/step  ETA %s%s",
                 terminal_ ? "\r" : "", name_.c_str(), t, duration_, ms_per_step,
                 human_duration(eta).c_str(), terminal_ ? "    " : "\n");
  }
  void finish(double t, double ms_per_step, Verdict verdict) {
    if (!shown_) return;
    std::fprintf(stderr, "%s  %-10s t = %7.3f / %.3f s  %8.3f ms/step  %s%s\n",
                 terminal_ ? "\r" : "", name_.c_str(), t, duration_, ms_per_step,
                 to_string(verdict), terminal_ ? "            " : "");
  }

 private:
  bool enabled_;
  std::string name_;
  double duration_;
  bool terminal_;
  bool shown_ = false;
  Clock::time_point started_ = Clock::now(), last_ = Clock::now();
};

// one backend run as it goes: the model, the sampling schedule and the energy the run started
// with. run() steps it to the end, or to the first verdict, signal or watchdog.
class BackendRunner {
 public:
  BackendRunner(const Scene& scene, const Weave& weave, const BackendInfo& info,
                const RunOptions& options, const SampleHook& hook)
      : scene_(scene),
        weave_(weave),
        options_(options),
        hook_(hook),
        scale_(energy_scale(scene, weave)),
        masses_(ring_masses(scene, weave)) {
    OpenedBackend opened = open_backend(scene, weave, info, options.threads);
    backend_ = std::move(opened.model);
    run_.name = info.name;
    run_.knobs = std::move(opened.knobs);
    run_.dt = run_.knobs.at("dt");
    total_steps_ = std::max(1LL, std::llround(scene.duration / run_.dt));
    steps_per_sample_ = std::max(1LL, std::llround(scene.sample_interval / run_.dt));
    metric_options_.other_pairs = options.other_pair_metrics;
  }

  BackendRun run() {
    started_ = Clock::now();
    Progress progress(options_.progress, run_.name, scene_.duration);
    bool going = sample(0);
    for (long long step = 1; going && step <= total_steps_; ++step) {
      const StepStatus status = timed_step();
      const bool due = step % steps_per_sample_ == 0 || step == total_steps_;
      // a backend that reports a non-finite state ends the run with a sample of that state
      if (due || status != StepStatus::ok) going = sample(step);
      if (going && status != StepStatus::ok) {
        end(Verdict::non_finite);
        break;
      }
      // a signal or the watchdog end the run here, with a last sample of where it got to
      if (going && step < total_steps_ && (interrupted() || watchdog_expired())) {
        if (step % steps_per_sample_ != 0) sample(step);  // unless just sampled
        end(interrupted() ? Verdict::interrupted : Verdict::watchdog);
        break;
      }
      progress.update(step * run_.dt, run_.ms_per_step());
    }
    progress.finish(run_.steps * run_.dt, run_.ms_per_step(), run_.verdict);
    finish();
    return std::move(run_);
  }

 private:
  // step: the only thing timed
  StepStatus timed_step() {
    const auto before = Clock::now();
    const StepStatus status = backend_->step(run_.dt);
    const double wall = seconds_since(before);
    run_.wall_s += wall, interval_wall_ += wall;
    ++interval_steps_, ++run_.steps;
    return status;
  }

  bool watchdog_expired() const {
    return options_.max_wall_seconds > 0.0 && seconds_since(started_) > options_.max_wall_seconds;
  }

  void end(Verdict verdict) {
    run_.stable = false;
    run_.verdict = verdict;
  }

  // energy gained since step 0 (which sets the baseline), J; 0 for a frame that is not finite
  double energy_growth(const Metrics& m, long long step) {
    if (m.non_finite > 0) return 0.0;
    const double potential = potential_energy(frame_, scene_, masses_);
    if (step == 0) {
      potential_start_ = potential, kinetic_start_ = m.kinetic_energy;
      energy_start_ = potential + m.kinetic_energy;
    }
    return potential + m.kinetic_energy - energy_start_;
  }

  // sample: metrics of the current frame, the stability checks on them, then the hook.
  // False once the run is unstable.
  bool sample(long long step) {
    backend_->frame(frame_);
    Sample s;
    s.t = frame_.t;
    s.metrics = measure(frame_, weave_, scene_, metric_options_);
    s.step_wall_ms = interval_steps_ ? 1e3 * interval_wall_ / interval_steps_ : 0.0;
    interval_wall_ = 0.0, interval_steps_ = 0;
    const double growth = energy_growth(s.metrics, step);
    if (s.metrics.non_finite == 0)
      run_.peak_stretch = std::max(run_.peak_stretch, s.metrics.max_stretch);
    if (const auto verdict = verdict_of(s.metrics, scene_, growth, scale_)) end(*verdict);
    if (hook_) hook_(frame_, s);
    run_.last = s;
    ++run_.samples;
    return run_.stable;
  }

  // the final frame, its hash, the stage profile and the two flags
  void finish() {
    backend_->frame(run_.final_frame);
    run_.hash = frame_hash(run_.final_frame);
    run_.stages = backend_->profile().stages();
    run_.residual = backend_->profile().residual();
    if (weave_.type != WeaveType::grid && run_.samples > 0)
      run_.overstretched = run_.peak_stretch > 1.0 + kOverstretchTolerance;
    if (run_.stable && run_.final_metrics().non_finite == 0) {
      // settled: little kinetic energy left of what gravity and the initial velocity gave the run
      const double given = std::max(
          potential_start_ - potential_energy(run_.final_frame, scene_, masses_) + kinetic_start_,
          0.0);
      run_.settled =
          run_.final_metrics().kinetic_energy <= kSettledEnergyFraction * given + 1e-12 * scale_;
    }
  }

  const Scene& scene_;
  const Weave& weave_;
  const RunOptions& options_;
  const SampleHook& hook_;
  std::unique_ptr<Backend> backend_;
  const double scale_;                // J, energy scale of the scene
  const std::vector<double> masses_;  // (rings) kg
  BackendRun run_;
  long long total_steps_ = 0, steps_per_sample_ = 0;
  MetricOptions metric_options_;
  RingFrame frame_;  // the frame last sampled
  double energy_start_ = 0.0, potential_start_ = 0.0, kinetic_start_ = 0.0;  // J, at step 0
  double interval_wall_ = 0.0;  // s of step() since the previous sample
  long long interval_steps_ = 0;
  Clock::time_point started_;  // when stepping began, for the watchdog
};

}  // namespace

bool SceneRun::all_stable() const {
  for (const auto& run : runs) {
    if (!run.stable) return false;
  }
  return true;
}

BackendRun run_backend(const Scene& scene, const Weave& weave, const std::string& name,
                       const RunOptions& options, const SampleHook& hook) {
  const BackendInfo* info = find_backend(name);
  if (!info) throw SceneError("unknown backend '" + name + "'");
  return run_backend(scene, weave, *info, options, hook);
}

BackendRun run_backend(const Scene& scene, const Weave& weave, const BackendInfo& info,
                       const RunOptions& options, const SampleHook& hook) {
  BackendRunner runner(scene, weave, info, options, hook);
  return runner.run();
}

}  // namespace chainmail
