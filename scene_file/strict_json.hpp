// Strict JSON for scene text: the limits on it, the strict parser and --set overrides
// (docs/scene-file.md). Part of the scene-file library (scene_file.hpp includes it); the text
// layer (scene_file_text.cpp) implements it, so that it needs nothing of the scene reader.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

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

// apply one "dotted.key=value" override to a raw scene document; throws SceneError. The value is
// strict JSON when it parses as JSON (1e400 and duplicate keys are errors), else a plain string
void apply_override(nlohmann::json& document, const std::string& assignment,
                    const std::string& file);

}  // namespace chainmail
