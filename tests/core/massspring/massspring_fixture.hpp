// The mass-spring cloth model's test fixtures: scene documents, the settings a cloth scene file
// asks for, a small simulation wrapper. Shared by the mass-spring test files.
#pragma once

#include <algorithm>
#include <string>

#include <nlohmann/json.hpp>

#include "core/massspring/massspring.hpp"
#include "core/spatial_hash.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail::massspring::test {

inline const std::string kClothDir = std::string(CHAINMAIL_SOURCE_DIR) + "/bench/scenes/cloth/";
constexpr double kDt = 1.0 / 2700.0;

// a cloth scene document: rows x cols masses, level in the x/z plane at height 1 m
inline nlohmann::json grid_document(int rows, int cols, double spacing) {
  return {{"name", "test"},
          {"weave",
           {{"type", "grid"},
            {"rows", rows},
            {"cols", cols},
            {"plane", "xz"},
            {"center", {0.0, 1.0, 0.0}},
            {"spacing", spacing}}},
          {"duration", 1.0}};
}

// the model settings a cloth scene file asks for under backends.massspring
inline Settings settings_of(const Scene& scene) {
  const KnobSection& k = scene.backends.at("massspring");
  const auto value = [&](const char* name, double fallback) {
    const auto it = k.find(name);
    return it == k.end() ? fallback : it->second.value;
  };
  Settings s;
  s.ks = value("ks", s.ks);
  s.shear_ks = value("shear_ks", s.shear_ks);
  s.bend_ks = value("bend_ks", s.bend_ks);
  s.damping_percent = value("damping_percent", s.damping_percent);
  s.correction_passes = static_cast<int>(value("correction_passes", s.correction_passes));
  s.max_extension = value("max_extension", s.max_extension);
  s.correct_all = value("correct_all", s.correct_all ? 1.0 : 0.0) != 0.0;
  s.thickness = value("thickness", s.thickness);
  s.areal_density = value("areal_density", s.areal_density);
  s.self_collision = scene.self_contact;
  return s;
}

struct Sim {
  Scene scene;
  Weave weave;
  Model model;
  State state;
  StageProfile profile;

  Sim(const Scene& s, const Settings& settings)
      : scene(s),
        weave(make_weave(s.weave, s.ring)),
        model(make_model(scene, weave, settings)),
        state(make_state(model, weave.rest_position)) {}
  void run(int steps, double dt = kDt) {
    for (int k = 0; k < steps; ++k) step(model, state, dt, profile);
  }
  double kinetic_energy() const {
    double e = 0.0;
    for (int m = 0; m < model.size(); ++m)
      e += 0.5 * model.mass[m] * state.velocity(m).squaredNorm();
    return e;
  }
  double max_stretch() const {
    double worst = 0.0;
    for (const Spring& s : model.springs) {
      worst = std::max(worst, (state.position.col(s.b) - state.position.col(s.a)).norm() / s.rest);
    }
    return worst;
  }
};

inline Scene cloth_scene(const std::string& file) {
  return load_scene_file(kClothDir + file);
}

// smallest distance between any two masses (pairs within `radius` only; radius if none)
inline double min_pair_distance(const Positions& x, double radius) {
  SpatialHash hash;
  hash.build(x, radius);
  double closest = radius;
  hash.for_each_pair(
      x, radius, [&](int i, int j) { closest = std::min(closest, (x.col(i) - x.col(j)).norm()); });
  return closest;
}

}  // namespace chainmail::massspring::test
