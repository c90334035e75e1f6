// SharedModel from several threads: steps serialised, every frame read whole, the same final
// hash as one thread stepping alone (run under the asan preset too).
#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "bench/harness/run/shared_model.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

constexpr int kSteps = 24;

Scene curtain(int side) {
  return scene_from_json(
      json{{"name", "threads_curtain"},
           {"weave", {{"type", "4in1"}, {"rows", side}, {"cols", side}, {"plane", "xy"}}},
           {"pins", json::array({{{"edge", "top"}}})},
           {"duration", 0.2},
           {"backends", {{"plausible", json::object()}}}},
      "test");
}

// the hash after each step of one thread stepping alone (index 0: the start)
std::vector<std::uint64_t> serial_hashes(const Scene& scene, int threads) {
  SharedModel model(scene, "plausible", threads);
  const double dt = model.knobs().at("dt");
  std::vector<std::uint64_t> hashes;
  RingFrame frame;
  model.read_frame(frame);
  hashes.push_back(frame_hash(frame));
  for (int k = 0; k < kSteps; ++k) {
    EXPECT_TRUE(model.step(dt));
    model.read_frame(frame);
    hashes.push_back(frame_hash(frame));
  }
  return hashes;
}

TEST(SharedModel, FourThreadsSteppingAndReadingOneModelSeeWholeFrames) {
  const Scene scene = curtain(16);
  const std::vector<std::uint64_t> serial = serial_hashes(scene, 1);
  const std::set<std::uint64_t> states(serial.begin(), serial.end());
  SharedModel model(scene, "plausible", 2);
  const double dt = model.knobs().at("dt");
  std::atomic<int> torn{0}, reads{0};
  std::atomic<bool> stepping{true};
  std::vector<std::thread> team;
  for (int t = 0; t < 4; ++t) {
    team.emplace_back([&] {
      for (int k = 0; k < kSteps / 4; ++k) model.step(dt);
    });
  }
  std::thread reader([&] {
    RingFrame frame;
    while (stepping.load()) {
      model.read_frame(frame);
      if (!states.count(frame_hash(frame))) ++torn;  // a frame between two steps is one of them
      ++reads;
    }
  });
  for (std::thread& t : team) t.join();
  stepping = false;
  reader.join();
  RingFrame last;
  model.read_frame(last);
  EXPECT_EQ(model.steps(), kSteps);
  EXPECT_EQ(frame_hash(last), serial.back());
  EXPECT_EQ(torn.load(), 0) << "of " << reads.load() << " reads";
}

TEST(SharedModel, EightThreadsEachWithTheirOwnModelAgreeWithOne) {
  const Scene scene = curtain(12);
  const std::uint64_t expected = serial_hashes(scene, 1).back();
  std::vector<std::uint64_t> hashes(8, 0);
  std::vector<std::thread> team;
  for (int t = 0; t < 8; ++t) {
    team.emplace_back([&, t] { hashes[t] = serial_hashes(scene, 1 + t % 2).back(); });
  }
  for (std::thread& t : team) t.join();
  for (int t = 0; t < 8; ++t) EXPECT_EQ(hashes[t], expected) << "thread " << t;
}

TEST(SharedModel, RefusesTheStepArgumentsTheCommandLineRefuses) {
  const SharedModel model(curtain(4), "plausible", 1);
  const double inf = std::numeric_limits<double>::infinity();
  for (const double dt : {0.0, -1e-3, inf, -inf, std::numeric_limits<double>::quiet_NaN(), 1e9}) {
    try {
      model.check_step(dt, 1);
      ADD_FAILURE() << "dt " << dt << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("dt: ", 0), 0u) << e.what();
    }
  }
  for (const long long n : {0LL, -5LL}) {
    EXPECT_THROW(model.check_step(model.knobs().at("dt"), n), std::invalid_argument);
  }
  EXPECT_NO_THROW(model.check_step(model.knobs().at("dt"), 1));
  EXPECT_THROW(SharedModel(curtain(4), "plausible", -1), std::invalid_argument);
}

}  // namespace
}  // namespace chainmail
