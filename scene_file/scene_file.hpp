// Scene files: strict JSON text -> a validated Scene (every key checked, defaults filled in), and
// a Scene -> its resolved JSON document (docs/scene-file.md). The models in core/ see only the
// plain Scene; JSON stays here.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scene.hpp"
// the strict parser and --set overrides, part of this interface
#include "scene_file/strict_json.hpp"

namespace chainmail {

// parse + validate; throws SceneError naming file and key
Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});
Scene scene_from_json(const nlohmann::json& document, const std::string& file);

// the resolved scene: every key with its value, defaults filled in, a pin by index as
// [row, col], camera position and target only when fixed, knob sections as written (integers as
// integers). scene_from_json of it gives the same scene; summary.json embeds it as "scene"
nlohmann::json scene_to_json(const Scene& scene);

}  // namespace chainmail
