// Metrics over RingFrames (names are the CSV columns and summary keys, see docs/metrics.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

struct Metrics {
  double max_stretch = 0.0;  // over linked pairs: centre distance / 2(c - a)
  double mean_stretch = 0.0;
  long long penetrating_linked = 0;         // neighbour pairs whose tori interpenetrate
  long long penetrating_other = 0;          // other pairs whose tori interpenetrate
  double penetration_max_linked = 0.0;      // m, 2a - centre-circle distance over penetrating
  double penetration_mean_linked = 0.0;     // m   neighbour pairs (0 when none)
  double penetration_max_other = 0.0;       // m, the same over penetrating other pairs
  double penetration_mean_other = 0.0;      // m
  long long broken_links = 0;               // neighbour pairs no longer linked
  long long false_links = 0;                // other pairs now linked
  std::optional<double> drape_coefficient;  // Cusick, scenes with a support only
  std::optional<double> drape_rms;          // m, against the reference run
  double kinetic_energy = 0.0;              // J, translational
  double max_speed = 0.0;                   // m/s
  long long non_finite = 0;  // NaN / inf entries in the frame (counted, not crashed on)
};

// metric column names in CSV order
const std::vector<std::string>& metric_names();
// value of a metric by name (NaN for absent optional metrics)
double metric_value(const Metrics& m, const std::string& name);

struct MetricOptions {
  bool other_pairs = true;  // penetrating_other / false_links need a broad phase over all rings
};

// everything but drape_rms (which needs a reference frame)
Metrics measure(const RingFrame& frame, const Weave& weave, const Scene& scene,
                const MetricOptions& options = {});

// RMS distance of ring centres between two frames of the same weave, m
double drape_rms(const RingFrame& frame, const RingFrame& reference);

// area of the union of ring disks (radius c) projected on the x/z plane, m^2 (rasterised)
double projected_area(const RingFrame& frame, double centre_radius, double cell);
// Cusick's drape coefficient (A_shadow - A_support) / (A_flat - A_support)
double drape_coefficient(const RingFrame& frame, const RingFrame& flat, const Support& support,
                         double centre_radius);

// relative error of a chain's sag against the catenary of the same span and length
// (length = links x 2(c - a)); absent unless the scene is a chain pinned at both ends at equal
// height
std::optional<double> catenary_error(const Scene& scene, const Weave& weave,
                                     const RingFrame& frame);

}  // namespace chainmail
