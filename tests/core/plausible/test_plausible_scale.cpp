// The plausible model on large sheets: long-range attachments to the pins, substeps where the
// Newton steps are too dear, and data-parallel sweeps whose result does not depend on threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

#include "core/plausible/pin_attachments.hpp"
#include "core/plausible/pin_paths.hpp"
#include "core/plausible/plausible.hpp"
#include "core/plausible/plausible_sweep.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

Scene hanging(const std::string& type, int rows, int cols, bool colliders = false) {
  json scene = {
      {"name", "hanging"},
      {"weave",
       {{"type", type}, {"rows", rows}, {"cols", cols}, {"plane", "xy"}, {"center", {0, 0.3, 0}}}},
      {"pins", json::array({{{"edge", "top"}}})},
      {"features", {{"self_contact", true}}},
      {"duration", 1.0}};
  if (type == "chain") scene["pins"] = json::array({{{"ring", 0}}, {{"ring", cols - 1}}});
  if (colliders) {
    // a ball the sheet falls onto, so the colliders' loop runs on the threads too
    scene["colliders"] =
        json::array({{{"type", "sphere"}, {"center", {0, 0.2, 0.02}}, {"radius", 0.03}}});
  }
  return scene_from_json(scene, "test");
}

double longest_link_stretch(const PlausibleSim& sim, const Weave& weave, double inner) {
  double longest = 0.0;  // m
  for (const RingPair& link : weave.links) {
    longest = std::max(
        longest, (sim.state().position.col(link.a) - sim.state().position.col(link.b)).norm());
  }
  return longest / inner;
}

// the sweeps' ways of running, all of them giving the same bits
struct SweepWay {
  bool vector = true;
};

std::uint64_t run_hash(const Scene& scene, int threads, int steps,
                       const PlausibleSettings& settings = {}, SweepWay way = {}) {
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.set_threads(threads);
  sim.set_rings_per_thread(1);  // small sheets on the threads too
  sim.set_vector_sweeps(way.vector);
  sim.reset(scene, weave, settings);
  for (int s = 0; s < steps; ++s) sim.step(0.004);
  RingFrame frame;
  sim.frame(frame);
  return frame_hash(frame);
}

TEST(PlausibleScale, AttachmentsBoundEveryRingByItsLinksToThePins) {
  // a ring k links from a pin is at most k longest links from it (triangle inequality): in the
  // rest layout, whose links are all shorter, every attachment holds; each ring below a pinned
  // edge is attached to pins at exactly its depth, the two farthest apart of them
  const Scene scene = hanging("4in1", 12, 10);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const std::vector<int> pinned = resolve_pins(scene, weave);
  const PinPaths paths = pin_paths(weave, pinned);
  const double link = 0.0077;  // m, longer than any rest link (0.894 ID = 7.2 mm)
  const PinAttachments lists = pin_attachments(weave, paths, pinned, link);
  ASSERT_EQ(lists[0].size(), paths.order.size());   // every ring below the pins, once
  EXPECT_GT(lists[1].size(), lists[0].size() / 2);  // most rings reach two distinct pins
  for (const auto& list : lists) {
    std::vector<int> seen;
    for (const PinAttachment& a : list) {
      seen.push_back(a.ring);
      EXPECT_EQ(paths.depth[a.pin], 0);
      EXPECT_NEAR(a.max_distance, paths.depth[a.ring] * link, 1e-15);
      const double distance =
          (weave.rest_position.col(a.ring) - weave.rest_position.col(a.pin)).norm();
      EXPECT_LE(distance, a.max_distance);
      // no pin is fewer links away than the depth: the distance along the rows to the pin is
      // at most half a row spacing per link (4-in-1 links step half a ring sideways)
      const double sideways = std::abs(
          weave.row_axis.dot(weave.rest_position.col(a.ring) - weave.rest_position.col(a.pin)));
      EXPECT_LE(sideways, paths.depth[a.ring] * 0.5 * 0.8 * 0.008 + 1e-12);
    }
    std::sort(seen.begin(), seen.end());
    EXPECT_TRUE(std::adjacent_find(seen.begin(), seen.end()) == seen.end());  // once per list
  }
}

TEST(PlausibleScale, ChainMiddleRingIsHeldByBothEnds) {
  const Scene scene = hanging("chain", 1, 21);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const std::vector<int> pinned = resolve_pins(scene, weave);
  const PinAttachments lists = pin_attachments(weave, pin_paths(weave, pinned), pinned, 1.0);
  int middle = 0;
  for (const auto& list : lists) {
    for (const PinAttachment& a : list) {
      if (a.ring != 10) continue;
      ++middle;
      EXPECT_DOUBLE_EQ(a.max_distance, 10.0);
    }
  }
  EXPECT_EQ(middle, 2);
}

TEST(PlausibleScale, LargeHangingSheetKeepsItsLinksWithinTheRings) {
  // 64 x 64 rings: released from the layout, the sheet falls until
  // the links go taut. A real link cannot grow past the inner diameter; with the attachments and
  // the sweeps spread over substeps none does, while the same sweeps in one pass let it stretch
  const Scene scene = hanging("4in1", 64, 64);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const double inner = scene.ring.inner_diameter();
  auto peak_stretch = [&](const PlausibleSettings& settings) {
    PlausibleSim sim;
    sim.reset(scene, weave, settings);
    double peak = 0.0;
    for (int s = 0; s < 100; ++s) {
      sim.step(0.004);
      peak = std::max(peak, longest_link_stretch(sim, weave, inner));
    }
    return peak;
  };
  const double shipped = peak_stretch(PlausibleSettings{});
  PlausibleSettings plain;
  plain.substeps = 1;
  plain.pin_attachments = false;
  const double sweeps_alone = peak_stretch(plain);
  std::printf("64x64 curtain, 0.4 s: peak stretch %.4f shipped, %.4f plain sweeps\n", shipped,
              sweeps_alone);
  EXPECT_LE(shipped, 1.0);
  EXPECT_GT(sweeps_alone, 1.0);
}

TEST(PlausibleScale, ThreadCountDoesNotChangeTheResult) {
  // same bits on 1, 2 and 3 threads: a sheet large enough for every loop to split (self-contact,
  // attachments, substeps), one on a sphere (colliders), and a small one on the Newton path
  const Scene large = hanging("4in1", 48, 48);
  const Scene ball = hanging("4in1", 48, 48, true);
  const Scene small = hanging("4in1", 12, 12);
  for (const Scene* scene : {&large, &ball, &small}) {
    const std::uint64_t one = run_hash(*scene, 1, 40);
    EXPECT_EQ(run_hash(*scene, 2, 40), one);
    EXPECT_EQ(run_hash(*scene, 3, 40), one);
  }
}

TEST(PlausibleScale, SmallSheetStepsOnTheThreadsItsRingsAreWorth) {
  // a thread per kRingsPerThread rings at most, never more than asked, at least one
  const Scene scene = hanging("4in1", 12, 12);  // 144 rings
  const Weave weave = make_weave(scene.weave, scene.ring);
  auto step_threads = [&](int threads, int rings_per_thread) {
    PlausibleSim sim;
    sim.set_threads(threads);
    if (rings_per_thread > 0) sim.set_rings_per_thread(rings_per_thread);
    sim.reset(scene, weave, {});
    sim.step(0.004);
    return sim.step_threads();
  };
  EXPECT_EQ(step_threads(4, 0), 1);  // the default: 144 rings are worth one thread
  EXPECT_EQ(step_threads(4, 50), 2);
  EXPECT_EQ(step_threads(2, 10), 2);
  EXPECT_EQ(step_threads(1, 1), 1);
}

TEST(PlausibleScale, BandsHoldEveryConstraintOnceNextToItsBand) {
  // 48 x 48 rings, the sweeps in bands: each attachment, edge
  // and diagonal is in exactly one stage's band, its rings in that band or the next, and a stage
  // (an attachment list, a colour) moves each ring at most once
  const Scene scene = hanging("4in1", 48, 48);
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  const PlausibleModel& model = sim.model();
  const SweepBands& bands = model.bands;
  ASSERT_GE(bands.bands(), 4);
  EXPECT_EQ(bands.first_ring.front(), 0);
  EXPECT_EQ(bands.first_ring.back(), weave.size());
  auto band_of = [&](int ring) {
    return static_cast<int>(
               std::upper_bound(bands.first_ring.begin(), bands.first_ring.end(), ring) -
               bands.first_ring.begin()) -
           1;
  };
  size_t attachments = 0, edges = 0, diagonals = 0;
  for (const SweepBands::Stage& stage : bands.stages) {
    std::vector<int> moved(weave.size(), 0);
    for (int k = 0; k < bands.bands(); ++k) {
      for (int item = stage.band_start[k]; item < stage.band_start[k + 1]; ++item) {
        if (stage.kind == SweepBands::Kind::attachments) {
          const PinAttachment& a = model.attachments[stage.list][item];
          EXPECT_EQ(band_of(a.ring), k);
          ++moved[a.ring];
          ++attachments;
          continue;
        }
        const EdgeConstraint& e =
            (stage.kind == SweepBands::Kind::edges ? model.edges : model.diagonals)[item];
        const int low = std::min(e.a, e.b), high = std::max(e.a, e.b);
        EXPECT_EQ(band_of(low), k);
        EXPECT_LE(band_of(high), k + 1);
        ++moved[e.a];
        ++moved[e.b];
        ++(stage.kind == SweepBands::Kind::edges ? edges : diagonals);
      }
    }
    EXPECT_LE(*std::max_element(moved.begin(), moved.end()), 1);
  }
  EXPECT_EQ(attachments, model.attachments[0].size() + model.attachments[1].size());
  EXPECT_EQ(edges, model.edges.size());
  EXPECT_EQ(diagonals, model.diagonals.size());
  EXPECT_GT(diagonals, 0u);
}

// the oracle of PlausibleSim::sweep_links: the attachment lists, then the edges and the diagonals
// colour by colour, each item alone, in list order (a colour's items share no ring, so any order
// within it gives the same bits); the largest violation met, m
double coloured_sweep(const PlausibleModel& model, Positions& position) {
  double* const x = position.data();
  const double* const w = model.inverse_mass.data();
  double worst = 0.0;
  for (const std::vector<PinAttachment>& list : model.attachments) {
    for (const PinAttachment& item : list) worst = std::max(worst, sweep_attachment(x, item));
  }
  for (const std::vector<EdgeConstraint>* pairs : {&model.edges, &model.diagonals}) {
    for (const EdgeConstraint& pair : *pairs) worst = std::max(worst, sweep_pair(x, w, pair));
  }
  return worst;
}

TEST(PlausibleScale, BandedSweepGivesTheColouredSweepsBits) {
  // the banded sweep solves each pair on the positions the colour-by-colour sweep gives it: the
  // same bits, on 1 and 3 threads (3: runs of bands meeting at two edges), with the blocks in
  // AVX2 or in portable lanes; a 4-in-1 sheet (attachments, diagonals) and a chain
  for (const Scene& scene : {hanging("4in1", 48, 48), hanging("chain", 1, 301)}) {
    const Weave weave = make_weave(scene.weave, scene.ring);
    for (const int threads : {1, 3}) {
      for (const bool vector : {true, false}) {
        PlausibleSim sim;
        sim.set_threads(threads);
        sim.set_rings_per_thread(1);
        sim.set_vector_sweeps(vector);
        sim.reset(scene, weave, {});
        ASSERT_GE(sim.model().bands.bands(), 4);  // 3 threads get runs of bands
        for (int check = 0; check < 4; ++check) {
          for (int s = 0; s < 10; ++s) sim.step(0.004);
          const Positions start = sim.state().position;
          Positions expected = start;
          const double expected_worst = coloured_sweep(sim.model(), expected);
          const double worst = sim.sweep_links().worst();
          EXPECT_EQ(worst, expected_worst) << threads << " threads, check " << check;
          EXPECT_TRUE((sim.state().position.array() == expected.array()).all())
              << threads << " threads, vector " << vector << ", check " << check;
          EXPECT_GT(worst, 0.0);  // the sweep had something to do
          sim.mutable_state().position = start;
        }
      }
    }
  }
}

TEST(PlausibleScale, VectorLanesGiveTheScalarBitsOnEveryWeave) {
  // the lane kernels' AVX2 build against the portable one (set_vector_sweeps): a long chain (its
  // links alternate in adjacent sets), a grid, and a 4-in-1 sheet falling onto a ball (colliders:
  // their push, the friction after the velocity pass), each with a ring count that leaves a tail
  // of fewer than four rings
  const Scene chain = hanging("chain", 1, 2047);
  const Scene grid = scene_from_json({{"name", "grid"},
                                      {"weave",
                                       {{"type", "grid"},
                                        {"rows", 41},
                                        {"cols", 41},
                                        {"spacing", 0.006},
                                        {"plane", "xy"},
                                        {"center", {0, 0.3, 0}}}},
                                      {"pins", json::array({{{"edge", "top"}}})},
                                      {"features", {{"self_contact", true}}},
                                      {"duration", 1.0}},
                                     "test");
  const Scene ball = hanging("4in1", 47, 49, true);
  for (const Scene* scene : {&chain, &grid, &ball}) {
    const std::uint64_t scalar = run_hash(*scene, 2, 40, {}, {.vector = false});
    EXPECT_EQ(run_hash(*scene, 2, 40), scalar);
  }
}

TEST(PlausibleScale, SubstepControlKeepsEveryLinkWithinTheInnerDiameter) {
  // one sweep a substep leaves a stretch that grows with g (dt / substeps)^2 and with the rows a
  // sheet hangs by: a 24 x 24 curtain under 100 m/s^2 on a fixed 16 substeps pulls its longest
  // link past the inner diameter (1.0046 ID, first at step 105), which no two interlocked rings
  // can reach. With the substeps automatic the control adds substeps and sweeps (up to 33), and
  // the longest link stays within it at every step (0.990 ID at most)
  Scene scene = hanging("4in1", 24, 24);
  scene.gravity = Vec3(0.0, -100.0, 0.0);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const double inner = scene.ring.inner_diameter();  // m
  auto run = [&](const PlausibleSettings& settings, int& most_substeps) {
    PlausibleSim sim;
    sim.reset(scene, weave, settings);
    double peak = 0.0;
    most_substeps = 0;
    for (int s = 0; s < 200; ++s) {
      sim.step(0.004);
      peak = std::max(peak, longest_link_stretch(sim, weave, inner));
      most_substeps = std::max(most_substeps, sim.state().substeps);
    }
    return peak;
  };
  PlausibleSettings fixed;
  fixed.substeps = 16;
  int substeps = 0;
  EXPECT_GT(run(fixed, substeps), 1.0);
  const double controlled = run(PlausibleSettings{}, substeps);
  EXPECT_LE(controlled, 1.0);
  EXPECT_GT(substeps, 16);
  EXPECT_LE(substeps, PlausibleSim::kMaxSubsteps);
}

}  // namespace
}  // namespace chainmail
