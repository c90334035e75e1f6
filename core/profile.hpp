// Per-stage counters: which phases of a step ran, how often and for how long.
// A stage a scene does not need never runs, so it never appears here. Every backend names two
// stages alike: "colliders" (rings against the scene's colliders) and "self_contact" (rings
// that are not neighbours); the rest are each backend's own phases.
#pragma once

#include <chrono>
#include <map>
#include <string>

namespace chainmail {

struct StageStats {
  long long calls = 0;
  double seconds = 0.0;
};

// the constraint solve's convergence over a run, for a backend that solves to a tolerance
struct ResidualStats {
  long long steps = 0;        // steps whose solve reported a residual
  long long unconverged = 0;  // steps that ended above the tolerance (iteration caps reached)
  double last = 0.0;          // m, the last step's largest remaining violation
  double max = 0.0;           // m, the largest over the run
  double tolerance = 0.0;     // m, what a converged step stays below
};

class StageProfile {
 public:
  // time one stage: `auto scope = profile.scope("colliders");`
  class Scope {
   public:
    // null: times nothing (a thread other than the one that keeps the profile)
    explicit Scope(StageStats* stats)
        : stats_(stats), start_(stats ? std::chrono::steady_clock::now() : Clock::time_point{}) {}
    ~Scope() {
      if (!stats_) return;
      stats_->calls += 1;
      stats_->seconds += std::chrono::duration<double>(Clock::now() - start_).count();
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    using Clock = std::chrono::steady_clock;
    StageStats* stats_;
    Clock::time_point start_;
  };

  Scope scope(const std::string& stage) { return Scope(&stages_[stage]); }
  // times the stage only where `on` (the profile is kept by one thread of a team)
  Scope scope_if(bool on, const std::string& stage) {
    return Scope(on ? &stages_[stage] : nullptr);
  }
  const std::map<std::string, StageStats>& stages() const { return stages_; }

  // one step's final residual against its tolerance
  void record_residual(double residual, double tolerance) {
    residual_.steps += 1;
    if (residual > tolerance) residual_.unconverged += 1;
    residual_.last = residual;
    residual_.max = residual > residual_.max ? residual : residual_.max;
    residual_.tolerance = tolerance;
  }
  const ResidualStats& residual() const { return residual_; }

  void clear() {
    stages_.clear();
    residual_ = ResidualStats{};
  }

 private:
  std::map<std::string, StageStats> stages_;
  ResidualStats residual_;
};

}  // namespace chainmail
