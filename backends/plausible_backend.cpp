// Adapter: the paper's plausible model (core/plausible.hpp) behind the Backend interface.
#include "backends/backend.hpp"
#include "core/plausible.hpp"

namespace chainmail {
namespace {

class PlausibleBackend final : public Backend {
 public:
  const char* name() const override { return "plausible"; }
  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override {
    PlausibleSettings settings;
    settings.iterations = static_cast<int>(knobs.at("iterations"));
    settings.tolerance = knobs.at("tolerance");
    settings.newton_steps = static_cast<int>(knobs.at("newton_steps"));
    settings.link_geometry = knobs.at("link_geometry") != 0.0;
    settings.max_link_fraction = knobs.at("max_link_fraction");
    settings.damping = knobs.at("damping");
    settings.damp_rigid = knobs.at("damp_rigid") != 0.0;
    settings.repulsion_fraction = knobs.at("repulsion_fraction");
    settings.repulsion_spring = knobs.at("repulsion_spring") != 0.0;
    settings.repulsion_stiffness = knobs.at("repulsion_stiffness");
    settings.contact_skin = knobs.at("contact_skin");
    settings.contact_margin = knobs.at("contact_margin");
    settings.swivel = knobs.at("swivel") != 0.0;
    settings.swivel_extended = knobs.at("swivel_extended");
    settings.swivel_fit = knobs.at("swivel_fit") != 0.0;
    settings.shock_propagation = knobs.at("shock_propagation") != 0.0;
    sim_.reset(scene, weave, settings);
  }
  void step(double dt) override { sim_.step(dt); }
  void frame(RingFrame& out) const override { sim_.frame(out); }
  const StageProfile& profile() const override { return sim_.profile(); }

 private:
  PlausibleSim sim_;
};

}  // namespace

BackendInfo plausible_backend_info() {
  const PlausibleSettings d;
  using T = KnobSpec::Type;
  BackendInfo info;
  info.name = "plausible";
  info.cost_us_per_ring_step = 12.0;
  info.bytes_per_ring = 1000;
  info.summary = "the paper's mass-per-ring model: Provot edge constraints, repulsion, swivel";
  info.knobs = {
      {"dt", T::number, 0.004, 1e-6, 0.1, "time step, s"},
      {"iterations", T::integer, static_cast<double>(d.iterations), 1, 100000,
       "most constraint sweeps per step"},
      {"tolerance", T::number, d.tolerance, 0.0, 1.0,
       "sweeps stop once the largest violation met is below this fraction of the link length"},
      {"newton_steps", T::integer, static_cast<double>(d.newton_steps), 0, 10000,
       "most Newton steps on edges and colliders together after the sweeps (0: sweeps only)"},
      {"link_geometry", T::boolean, d.link_geometry ? 1.0 : 0.0, 0.0, 1.0,
       "largest neighbour distance from the ring geometry, by the rings' orientation"},
      {"max_link_fraction", T::number, d.max_link_fraction, 0.2, 1.0,
       "largest neighbour distance / inner diameter (without link_geometry, or where the "
       "geometry gives none)"},
      {"damping", T::number, d.damping, 0.0, 1000.0,
       "damping of motion other than rigid motion of the whole, 1/s"},
      {"damp_rigid", T::boolean, d.damp_rigid ? 1.0 : 0.0, 0.0, 1.0,
       "damping slows all motion, rigid motion included (a drag)"},
      {"repulsion_fraction", T::number, d.repulsion_fraction, 0.0, 2.0,
       "non-neighbour minimum distance (or repulsion spring range) / inner diameter"},
      {"repulsion_spring", T::boolean, d.repulsion_spring ? 1.0 : 0.0, 0.0, 1.0,
       "non-neighbours repel by the paper's spring (explicit) instead of a minimum distance"},
      {"repulsion_stiffness", T::number, d.repulsion_stiffness, 0.0, 1e9,
       "stiffness of the repulsion spring, N/m"},
      {"contact_skin", T::number, d.contact_skin, 0.0, 10.0,
       "repulsion candidate list margin, fraction of the range (0 = rebuild every step)"},
      {"contact_margin", T::number, d.contact_margin, 0.0, 1.0,
       "distance kept between a ring centre and a collider, m (0: the torus's extent along the "
       "collider normal from the ring's orientation)"},
      {"swivel", T::boolean, 1.0, 0.0, 1.0, "swivel rings into the 4-in-1 pattern"},
      {"shock_propagation", T::boolean, d.shock_propagation ? 1.0 : 0.0, 0.0, 1.0,
       "a constraint pass outward from the pins before the sweeps, moving only the far ring"},
      {"swivel_extended", T::number, d.swivel_extended, 0.0, 1.5707963267948966,
       "swivel angle at full extension, rad (0: the paper's a/c)"},
      {"swivel_fit", T::boolean, 0.0, 0.0, 1.0,
       "swivel at full extension fitted to the ring geometry (most neighbour clearance)"},
  };
  info.create = [] { return std::make_unique<PlausibleBackend>(); };
  return info;
}

}  // namespace chainmail
