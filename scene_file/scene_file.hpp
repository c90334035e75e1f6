// Scene files: strict JSON text -> a validated Scene (every key checked, defaults filled in), and
// a Scene -> its resolved JSON document (docs/scene-file.md). The models in core/ see only the
// plain Scene; JSON stays here.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scene.hpp"

namespace chainmail {

// limits on scene text (docs/scene-file.md). Nesting deeper than kMaxJsonDepth containers
// is refused while parsing, before anything recursive (copy, dump, compare) could overflow the
// stack; a file larger than kMaxSceneFileBytes is refused without reading it all
inline constexpr int kMaxJsonDepth = 64;
inline constexpr long long kMaxSceneFileBytes = 16LL << 20;  // 16 MiB

// strict JSON for scene text, comments allowed: refuses duplicate keys, numbers beyond double
// range and nesting deeper than kMaxJsonDepth. Throws SceneError "<source>: key '<path>': <what>"
// or "<source>: JSON syntax error at line L, column C: ..."; never a nlohmann exception
nlohmann::json parse_json_strict(const std::string& text, const std::string& source);

// parse + validate; throws SceneError naming file and key
Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});
Scene scene_from_json(const nlohmann::json& document, const std::string& file);
// apply one "dotted.key=value" override to a raw scene document; throws SceneError. The value is
// strict JSON when it parses as JSON (1e400 and duplicate keys are errors), else a plain string
void apply_override(nlohmann::json& document, const std::string& assignment,
                    const std::string& file);

// the resolved scene: every key with its value, defaults filled in, a pin by index as
// [row, col], camera position and target only when fixed, knob sections as written (integers as
// integers). scene_from_json of it gives the same scene; summary.json embeds it as "scene"
nlohmann::json scene_to_json(const Scene& scene);

}  // namespace chainmail
