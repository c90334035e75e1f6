// Mass-spring cloth model: springs, Verlet, the over-extension correction, contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "massspring_fixture.hpp"

namespace chainmail::massspring {
namespace {
using namespace test;

// --- springs -------------------------------------------------------------------------------------

TEST(MassSpring, HookeForceFollowsHookesLaw) {
  const Vec3 p0(0.0, 0.0, 0.0);
  // stretched along x by 0.2 of a rest length 1: pulled towards p1 with ks * 0.2
  Vec3 f = hooke_force(p0, Vec3(1.2, 0.0, 0.0), 1.0, 500.0);
  EXPECT_NEAR(f.x(), 100.0, 1e-9);
  EXPECT_NEAR(f.y(), 0.0, 1e-12);
  // compressed: pushed away
  f = hooke_force(p0, Vec3(0.0, 0.5, 0.0), 1.0, 500.0);
  EXPECT_NEAR(f.y(), -250.0, 1e-9);
  // at rest length, in any direction: no force
  EXPECT_LT(hooke_force(p0, Vec3(0.6, 0.0, 0.8), 1.0, 500.0).norm(), 1e-12);
  // along the spring, proportional to the extension
  const Vec3 p1(0.3, -0.4, 1.2);  // length 1.3
  f = hooke_force(p0, p1, 1.0, 40.0);
  EXPECT_NEAR(f.norm(), 40.0 * 0.3, 1e-9);
  EXPECT_NEAR(f.normalized().dot(p1.normalized()), 1.0, 1e-12);
}

TEST(MassSpring, SpringsFromGridTopologyWithRestLengths) {
  const double L0 = 0.1;
  const Scene scene = scene_from_json(grid_document(5, 6, L0), "test.json");
  const Weave weave = make_weave(scene.weave, scene.ring);
  Settings settings;
  settings.ks = 100.0, settings.shear_ks = 70.0, settings.bend_ks = 20.0;
  const auto springs = build_springs(weave, weave.rest_position, settings);
  int count[3] = {0, 0, 0};
  std::set<std::pair<int, int>> seen;
  for (const Spring& s : springs) {
    ++count[static_cast<int>(s.kind)];
    EXPECT_TRUE(seen.insert({std::min(s.a, s.b), std::max(s.a, s.b)}).second) << "duplicate";
    const auto gi = weave.grid[s.a], gj = weave.grid[s.b];
    const int di = std::abs(gi[0] - gj[0]), dj = std::abs(gi[1] - gj[1]);
    switch (s.kind) {
      case SpringKind::structural:
        EXPECT_EQ(di + dj, 1);
        EXPECT_NEAR(s.rest, L0, 1e-12);
        EXPECT_EQ(s.k, 100.0);
        break;
      case SpringKind::shear:
        EXPECT_TRUE(di == 1 && dj == 1);
        EXPECT_NEAR(s.rest, std::sqrt(2.0) * L0, 1e-12);
        EXPECT_EQ(s.k, 70.0);
        break;
      case SpringKind::bending:
        EXPECT_TRUE((di == 2 && dj == 0) || (di == 0 && dj == 2));
        EXPECT_NEAR(s.rest, 2.0 * L0, 1e-12);
        EXPECT_EQ(s.k, 20.0);
        break;
    }
  }
  // 6 cols x 5 rows: structural 5*5 + 6*4, shear 2*5*4, bending 4*5 + 6*3
  EXPECT_EQ(count[0], 49);
  EXPECT_EQ(count[1], 40);
  EXPECT_EQ(count[2], 38);
}

TEST(MassSpring, SpringForcePerKindMatchesHooke) {
  const Scene scene = scene_from_json(grid_document(4, 4, 0.1), "test.json");
  const Weave weave = make_weave(scene.weave, scene.ring);
  Settings settings;
  settings.ks = 300.0, settings.shear_ks = 200.0, settings.bend_ks = 50.0;
  settings.point_mass = 0.01;
  const Model full = make_model(scene, weave, settings);
  for (SpringKind kind : {SpringKind::structural, SpringKind::shear, SpringKind::bending}) {
    // one spring of this kind alone, no gravity; stretch it by moving its second end
    Model model = full;
    model.gravity = Vec3::Zero();
    const auto it = std::find_if(full.springs.begin(), full.springs.end(),
                                 [&](const Spring& s) { return s.kind == kind; });
    ASSERT_NE(it, full.springs.end());
    model.springs = {*it};
    Positions x = weave.rest_position;
    x.col(it->b) += Vec3(0.013, 0.021, -0.007);
    Positions force(3, model.size());
    accumulate_forces(model, x, force);
    const Vec3 d = x.col(it->b) - x.col(it->a);
    const double k = kind == SpringKind::structural ? 300.0
                     : kind == SpringKind::shear    ? 200.0
                                                    : 50.0;
    const Vec3 expected = k * (d.norm() - it->rest) * d.normalized();
    EXPECT_LT((Vec3(force.col(it->a)) - expected).norm(), 1e-9 * expected.norm());
    EXPECT_LT((Vec3(force.col(it->b)) + expected).norm(), 1e-9 * expected.norm());
    EXPECT_GT(expected.norm(), 0.0);
  }
}

TEST(MassSpring, RestLengthsComeFromTheRestLayoutOf4in1) {
  nlohmann::json doc = grid_document(6, 6, 0.1);
  doc["weave"] = {{"type", "4in1"}, {"rows", 6}, {"cols", 6}};
  const Scene scene = scene_from_json(doc, "test.json");
  const Weave weave = make_weave(scene.weave, scene.ring);
  const auto springs = build_springs(weave, weave.rest_position, Settings{});
  int structural = 0;
  for (const Spring& s : springs) {
    EXPECT_NEAR(s.rest, (weave.rest_position.col(s.b) - weave.rest_position.col(s.a)).norm(),
                1e-15);
    structural += s.kind == SpringKind::structural;
  }
  // the structural springs are exactly the weave's links
  EXPECT_EQ(structural, static_cast<int>(weave.links.size()));
}

TEST(MassSpring, MassFromArealDensityOrPointMass) {
  const Scene scene = cloth_scene("plane.json");
  const Weave weave = make_weave(scene.weave, scene.ring);
  Settings settings;
  settings.areal_density = 15.0;
  // 1 m^2 over 50 x 50 masses
  EXPECT_NEAR(area_per_mass(weave, weave.rest_position), 1.0 / 2500.0, 1e-15);
  EXPECT_NEAR(make_model(scene, weave, settings).mass[0], 15.0 / 2500.0, 1e-15);
  settings.areal_density = 0.0;
  settings.point_mass = scene.ring.mass();
  const Model model = make_model(scene, weave, settings);
  EXPECT_EQ(model.mass[123], scene.ring.mass());
}

// --- integration ---------------------------------------------------------------------------------

TEST(MassSpring, VerletFreeFallIsGtSquaredOverTwoWithinOrderDt) {
  for (double dt : {1e-3, 5e-4}) {
    const Scene scene = scene_from_json(grid_document(1, 1, 0.1), "test.json");
    Settings settings;
    settings.point_mass = 0.01;
    settings.damping_percent = 0.0;
    Sim sim(scene, settings);
    const int steps = static_cast<int>(std::lround(0.5 / dt));
    sim.run(steps, dt);
    const double t = steps * dt, g = 9.81;
    const double fallen = 1.0 - sim.state.position(1, 0);
    // Verlet from rest: x_n = g dt^2 n (n + 1) / 2 = g t^2 / 2 + g t dt / 2
    EXPECT_NEAR(fallen, 0.5 * g * t * t + 0.5 * g * t * dt, 1e-9);
    const double error = fallen - 0.5 * g * t * t;
    EXPECT_GT(error, 0.0);
    EXPECT_LE(error, 0.5 * g * t * dt * (1.0 + 1e-6));
    EXPECT_NEAR(sim.state.velocity(0).y(), -g * t, g * dt);
    EXPECT_EQ(sim.state.position(0, 0), 0.0);
  }
}

TEST(MassSpring, DerivedStiffnessStretchesAHangingColumnByTheAskedFraction) {
  // a column of 12 masses, 1 cm apart, hung from its top: ks = m g n / (2 s L)
  nlohmann::json doc = grid_document(12, 1, 0.01);
  doc["weave"]["plane"] = "xy";
  doc["pins"] = {{{"edge", "top"}}};
  const Scene scene = scene_from_json(doc, "test.json");
  Settings settings;
  settings.point_mass = 0.001;
  settings.damping_percent = 2.0;  // settles within the run
  Sim sim(scene, settings);
  EXPECT_NEAR(sim.model.settings.ks, 0.001 * 9.81 * 12.0 / (2.0 * 0.03 * 0.01), 1e-9);
  EXPECT_NEAR(sim.model.settings.shear_ks, kShearFraction * sim.model.settings.ks, 1e-12);
  EXPECT_NEAR(sim.model.settings.bend_ks, kBendFraction * sim.model.settings.ks, 1e-12);
  // the derived substeps keep the springs' highest frequency within reach of the step
  const int substeps = stable_substeps(sim.model, kDt);
  EXPECT_LE(highest_frequency(sim.model) * kDt / substeps, kVerletReach);
  sim.run(3 * 2700 * substeps, kDt / substeps);
  const auto y = sim.state.position.row(1);
  const double stretch = (y.maxCoeff() - y.minCoeff()) / (11 * 0.01) - 1.0;
  // the bending springs along the column (k_b over twice the length, stretched twice as far)
  // stiffen it by 4 kBendFraction
  EXPECT_NEAR(stretch, 0.03 / (1.0 + 4.0 * kBendFraction), 0.001);
  // twice the stretch asked, half the stiffness
  settings.stretch = 0.06;
  EXPECT_NEAR(Sim(scene, settings).model.settings.ks, 0.5 * sim.model.settings.ks, 1e-9);
  // given constants are kept, and so are the substeps they need
  settings.ks = 5000.0, settings.shear_ks = 5000.0, settings.bend_ks = 1000.0;
  const Sim stiff(scene, settings);
  EXPECT_EQ(stiff.model.settings.shear_ks, 5000.0);
  EXPECT_GT(stable_substeps(stiff.model, kDt), substeps);
}

// --- the over-extension correction ---------------------------------------------------------------

TEST(MassSpring, SinglePassCanLeaveASpringOverExtendedIteratedPassesFixIt) {
  // the document's case: A (pinned) - B - C; the right spring is over-extended, the left is not;
  // moving B to fix the right one over-extends the left one
  const std::vector<Spring> springs = {{0, 1, 1.0, 1.0}, {1, 2, 1.0, 1.0}};
  Eigen::VectorXd inv_mass(3);
  inv_mass << 0.0, 1.0, 1.0;
  Positions start(3, 3);
  start << 0.0, 1.05, 2.4, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  auto stretch = [](const Positions& x, int a, int b) { return (x.col(b) - x.col(a)).norm(); };

  Positions x = start;
  EXPECT_EQ(correct_overextension(springs, inv_mass, 0.1, x), 1);
  EXPECT_LE(stretch(x, 1, 2), 1.1 + 1e-12);
  EXPECT_GT(stretch(x, 0, 1), 1.1 + 1e-3);  // left spring now over-extended
  EXPECT_EQ(x(0, 0), 0.0);                  // pinned end did not move

  x = start;
  int passes = 0;
  while (correct_overextension(springs, inv_mass, 0.1, x) > 0 && passes < 200) ++passes;
  EXPECT_LT(passes, 200);
  EXPECT_LE(stretch(x, 0, 1), 1.1 * (1.0 + 1e-12));
  EXPECT_LE(stretch(x, 1, 2), 1.1 * (1.0 + 1e-12));
  EXPECT_EQ(x(0, 0), 0.0);
}

TEST(MassSpring, EnoughCorrectionPassesKeepEverySpringWithinTenPercent) {
  // a soft heavy cloth hanging from two corners stretches far past 10 % without the correction
  nlohmann::json doc = grid_document(8, 8, 0.05);
  doc["pins"] = {{{"corner", "top_left"}}, {{"corner", "top_right"}}};
  const Scene scene = scene_from_json(doc, "test.json");
  Settings settings;
  settings.ks = 20.0, settings.shear_ks = 20.0, settings.bend_ks = 5.0;
  settings.areal_density = 15.0;
  settings.correct_all = true;  // the document's correction: every spring
  double worst[3] = {0.0, 0.0, 0.0};
  const int passes[3] = {0, 1, 400};
  for (int c = 0; c < 3; ++c) {
    settings.correction_passes = passes[c];
    Sim sim(scene, settings);
    for (int k = 0; k < 810; ++k) {  // 0.3 s
      sim.run(1);
      worst[c] = std::max(worst[c], sim.max_stretch());
    }
  }
  EXPECT_GT(worst[0], 1.5);               // no correction: far over
  EXPECT_GT(worst[1], 1.1 + 1e-3);        // one pass: some spring stays over
  EXPECT_LE(worst[2], 1.1 * (1 + 1e-6));  // iterated to convergence: none over
  // the default correction holds the structural springs only: they stay within 10 %, the shear
  // and bending springs stretch further
  settings.correct_all = false;
  Sim sheet(scene, settings);
  double structural = 0.0, other = 0.0;
  for (int k = 0; k < 810; ++k) {
    sheet.run(1);
    for (const Spring& s : sheet.model.springs) {
      const Vec3 d = sheet.state.position.col(s.b) - sheet.state.position.col(s.a);
      double& worst_of_kind = s.kind == SpringKind::structural ? structural : other;
      worst_of_kind = std::max(worst_of_kind, d.norm() / s.rest);
    }
  }
  EXPECT_LE(structural, 1.1 * (1 + 1e-6));
  EXPECT_GT(other, 1.1 + 1e-3);
}

// --- pins, damping, determinism ------------------------------------------------------------------

TEST(MassSpring, PinnedMassesNeverMove) {
  Scene scene = cloth_scene("pinned4.json");
  Sim sim(scene, settings_of(scene));
  const std::vector<int> pins = resolve_pins(scene, sim.weave);
  ASSERT_EQ(pins.size(), 4u);
  for (int k = 0; k < 10; ++k) {
    sim.run(50);
    for (int p : pins) {
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(sim.state.position(c, p), sim.weave.rest_position(c, p));
    }
  }
  // and the rest of the cloth did move
  EXPECT_LT(sim.state.position.row(1).minCoeff(), 0.95);
}

// kinetic energy summed over the last second of 4 s, and the frame (of 1/30 s) from which on it
// stays below 1 mJ (-1: never), for a 12 x 12 cloth of 15 kg/m^2 released flat from its pins
struct Settling {
  double late_energy = 0.0;
  int settled_at = -1;
};
Settling settle(const nlohmann::json& pins, const Settings& settings) {
  nlohmann::json doc = grid_document(12, 12, 1.0 / 11.0);
  doc["pins"] = pins;
  const Scene scene = scene_from_json(doc, "test.json");
  Sim sim(scene, settings);
  Settling result;
  for (int k = 0; k < 120; ++k) {
    sim.run(90);
    const double e = sim.kinetic_energy();
    if (k >= 90) result.late_energy += e;
    if (e < 1e-3 && result.settled_at < 0) result.settled_at = k;
    if (e >= 1e-3) result.settled_at = -1;
  }
  return result;
}

TEST(MassSpring, HigherDampingBringsASwingingClothToRestSooner) {
  // pinned at three corners the cloth has no rigid motion left, so damping acts on all of it;
  // pinned at two corners it swings about their line, a rigid motion only the document's drag
  // (damp_rigid) slows
  const nlohmann::json three = {
      {{"corner", "top_left"}}, {{"corner", "top_right"}}, {{"corner", "bottom_left"}}};
  const nlohmann::json two = {{{"corner", "top_left"}}, {{"corner", "top_right"}}};
  for (const bool drag : {false, true}) {
    SCOPED_TRACE(drag ? "two corners, drag" : "three corners");
    Settings settings;
    settings.areal_density = 15.0;
    settings.damp_rigid = drag;
    Settling result[2];
    const double damping[2] = {0.02, 0.2};
    for (int c = 0; c < 2; ++c) {
      settings.damping_percent = damping[c];
      result[c] = settle(drag ? two : three, settings);
    }
    EXPECT_LT(result[1].late_energy, 0.1 * result[0].late_energy);
    ASSERT_GE(result[1].settled_at, 0);  // the damped cloth settled ...
    EXPECT_TRUE(result[0].settled_at < 0 ||
                result[0].settled_at > result[1].settled_at);  // ... before the other one
  }
}

TEST(MassSpring, SameSceneTwiceGivesBitIdenticalPositions) {
  const Scene scene = cloth_scene("sphere.json");
  Sim a(scene, settings_of(scene)), b(scene, settings_of(scene));
  a.run(600);
  b.run(600);
  ASSERT_EQ(a.state.position.size(), b.state.position.size());
  EXPECT_EQ(std::memcmp(a.state.position.data(), b.state.position.data(),
                        sizeof(double) * a.state.position.size()),
            0);
  EXPECT_GT(a.profile.stages().at("self_contact").calls, 0);
}

// --- colliders -----------------------------------------------------------------------------------

TEST(MassSpring, ProjectOutOfEachColliderType) {
  Collider plane;
  plane.type = Collider::Type::plane;
  plane.normal = Vec3::UnitY();
  Vec3 p(0.3, -0.02, 0.1), n;
  EXPECT_NEAR(project_out(plane, 0.0, p, n), 0.02, 1e-15);
  EXPECT_EQ(p.y(), 0.0);

  Collider sphere;
  sphere.type = Collider::Type::sphere;
  sphere.center = Vec3(1.0, 0.0, 0.0), sphere.radius = 0.5;
  p = Vec3(1.0, 0.3, 0.0);
  EXPECT_NEAR(project_out(sphere, 0.0, p, n), 0.2, 1e-15);
  EXPECT_NEAR((p - sphere.center).norm(), 0.5, 1e-15);

  Collider box;
  box.type = Collider::Type::box;
  box.half_extents = Vec3(1.0, 0.2, 1.0);
  p = Vec3(0.5, 0.15, -0.3);
  EXPECT_NEAR(project_out(box, 0.01, p, n), 0.06, 1e-12);
  EXPECT_NEAR(p.y(), 0.21, 1e-15);
  EXPECT_EQ(n, Vec3::UnitY());

  Collider cylinder;
  cylinder.type = Collider::Type::cylinder;
  cylinder.radius = 0.5, cylinder.half_height = 1.0;
  p = Vec3(0.4, 0.0, 0.0);
  EXPECT_NEAR(project_out(cylinder, 0.0, p, n), 0.1, 1e-15);
  EXPECT_NEAR(p.x(), 0.5, 1e-15);
  p = Vec3(0.0, 0.95, 0.1);
  EXPECT_NEAR(project_out(cylinder, 0.0, p, n), 0.05, 1e-12);
  EXPECT_NEAR(p.y(), 1.0, 1e-15);
  // outside: untouched
  p = Vec3(2.0, 0.0, 0.0);
  EXPECT_EQ(project_out(cylinder, 0.0, p, n), 0.0);
  EXPECT_EQ(p, Vec3(2.0, 0.0, 0.0));
}

TEST(MassSpring, FrictionSticksBelowTheLimitAndSlidesAbove) {
  const Vec3 normal = Vec3::UnitY();
  Vec3 p(0.001, 0.0, 0.0);
  apply_friction(Vec3::Zero(), normal, 0.01, 0.3, p);  // slide 1 mm < 0.3 * 10 mm: sticks
  EXPECT_LT(p.norm(), 1e-15);
  p = Vec3(0.01, 0.0, 0.0);
  apply_friction(Vec3::Zero(), normal, 0.01, 0.3, p);  // slide 10 mm: loses 3 mm
  EXPECT_NEAR(p.x(), 0.007, 1e-15);
}

TEST(MassSpring, NoMassInsideTheSphereAfterContact) {
  const Scene scene = cloth_scene("sphere.json");
  Sim sim(scene, settings_of(scene));
  const Collider& sphere = scene.colliders.at(0);
  int touching = 0;
  for (int frame = 0; frame < 20; ++frame) {  // 2/3 s, it lands at about 0.3 s
    sim.run(90);
    for (int m = 0; m < sim.model.size(); ++m) {
      const double r = (Vec3(sim.state.position.col(m)) - sphere.center).norm();
      ASSERT_GE(r, sphere.radius * (1.0 - 1e-12)) << "mass " << m << " at frame " << frame;
      touching += r < sphere.radius + 1e-4;
    }
  }
  EXPECT_GT(touching, 0);
}

TEST(MassSpring, NoMassBelowThePlaneAfterContact) {
  const Scene scene = cloth_scene("plane.json");
  Sim sim(scene, settings_of(scene));
  int touching = 0;
  for (int frame = 0; frame < 15; ++frame) {  // 0.5 s, it lands at about 0.32 s
    sim.run(90);
    for (int m = 0; m < sim.model.size(); ++m) {
      ASSERT_GE(sim.state.position(1, m), -1e-12) << "mass " << m << " at frame " << frame;
      touching += sim.state.position(1, m) < 1e-6;
    }
  }
  EXPECT_GT(touching, 0);
  EXPECT_EQ(sim.profile.stages().count("self_contact"), 0u);  // the scene turns it off
}

}  // namespace
}  // namespace chainmail::massspring
