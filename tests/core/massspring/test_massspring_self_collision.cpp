// Mass-spring cloth model: self-collision (thickness kept, the spatial hash's cell mixing).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_set>

#include "massspring_fixture.hpp"

namespace chainmail::massspring {
namespace {
using namespace test;

// --- self-collision ------------------------------------------------------------------------------

// the self-collision scene, run once for the tests below: snapshots every 1/10 s for 1.2 s
class SelfCollisionScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const Scene scene = cloth_scene("selfcollision.json");
    settings_ = new Settings(settings_of(scene));
    Sim sim(scene, *settings_);
    snapshots_ = new std::vector<Positions>{sim.state.position};
    worst_ = new double(settings_->thickness);
    for (int frame = 1; frame <= 36; ++frame) {
      sim.run(90);
      *worst_ = std::min(*worst_, min_pair_distance(sim.state.position, settings_->thickness));
      if (frame % 3 == 0) snapshots_->push_back(sim.state.position);
    }
    plane_ = new Collider(scene.colliders.at(0));
  }
  static void TearDownTestSuite() {
    delete settings_, delete snapshots_, delete worst_, delete plane_;
  }
  static Settings* settings_;
  static std::vector<Positions>* snapshots_;
  static double* worst_;
  static Collider* plane_;
};
Settings* SelfCollisionScene::settings_ = nullptr;
std::vector<Positions>* SelfCollisionScene::snapshots_ = nullptr;
double* SelfCollisionScene::worst_ = nullptr;
Collider* SelfCollisionScene::plane_ = nullptr;

TEST_F(SelfCollisionScene, MassesStayAtLeastTheThicknessApart) {
  ASSERT_EQ(settings_->thickness, 0.0095);
  EXPECT_GE(*worst_, settings_->thickness * (1.0 - 1e-4));
  // the cloth did fold onto itself: many non-neighbour masses sit at about the thickness
  int near = 0;
  SpatialHash hash;
  const Positions& last = snapshots_->back();
  hash.build(last, 1.05 * settings_->thickness);
  hash.for_each_pair(last, 1.05 * settings_->thickness, [&](int, int) { ++near; });
  EXPECT_GT(near, 50);
  for (int m = 0; m < last.cols(); ++m) {
    ASSERT_GE((Vec3(last.col(m)) - plane_->center).dot(plane_->normal), -1e-12);
  }
}

// cells sharing a bucket with another cell, for a given cell hash and table size
template <class Hash>
long long bucket_collisions(const Positions& x, double cell, int table, Hash hash) {
  std::set<std::array<long long, 3>> cells;
  for (int m = 0; m < x.cols(); ++m) {
    cells.insert({static_cast<long long>(std::floor(x(0, m) / cell)),
                  static_cast<long long>(std::floor(x(1, m) / cell)),
                  static_cast<long long>(std::floor(x(2, m) / cell))});
  }
  std::unordered_set<std::uint64_t> buckets;
  for (const auto& c : cells) buckets.insert(hash(c[0], c[1], c[2]) % table);
  return static_cast<long long>(cells.size() - buckets.size());
}

TEST_F(SelfCollisionScene, WellMixedHashCollidesLessThanTheDocumentsHash) {
  // the document's x + y^2 + z^3 (its absolute value, then modulo) against core's hash_cell,
  // same cells (the thickness), same table size as SpatialHash picks (2n + 1)
  auto document = [](long long x, long long y, long long z) {
    const long long h = x + y * y + z * z * z;
    return static_cast<std::uint64_t>(h < 0 ? -h : h);
  };
  auto mixed = [](long long x, long long y, long long z) { return hash_cell(x, y, z); };
  long long doc_total = 0, mixed_total = 0;
  for (const Positions& x : *snapshots_) {
    const int table = 2 * static_cast<int>(x.cols()) + 1;
    doc_total += bucket_collisions(x, settings_->thickness, table, document);
    mixed_total += bucket_collisions(x, settings_->thickness, table, mixed);
  }
  std::printf("bucket collisions over %zu snapshots: x + y^2 + z^3 %lld, hash_cell %lld\n",
              snapshots_->size(), doc_total, mixed_total);
  RecordProperty("document_hash_collisions", std::to_string(doc_total));
  RecordProperty("hash_cell_collisions", std::to_string(mixed_total));
  EXPECT_LT(mixed_total, doc_total);
}

}  // namespace
}  // namespace chainmail::massspring
