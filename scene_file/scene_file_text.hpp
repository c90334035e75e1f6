// Scene text helpers of the scene-file library: safe reading of a scene file and the pieces of
// its one-line messages, shared by the reader (scene_file.hpp) and the strict parser
// (strict_json.hpp).
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace chainmail {

// text as it may appear in a one-line message: control characters escaped, invalid utf-8
// replaced, long text cut
std::string shown(const std::string& text, std::size_t limit = 80);
// shortest text that reads back as the same double ("1e-06", "0.9", "1.9999999375")
std::string show_number(double x);
// whether an integer JSON value lies in [min, max]; parsed non-negative integers are unsigned,
// so 2^63 and above are compared as such, not wrapped
bool integer_in(const nlohmann::json& value, long long min, long long max);
// deepest container nesting of a document (one built in code may skip the parser), iteratively;
// stops counting past kMaxJsonDepth
int nesting_depth(const nlohmann::json& document);
// the whole scene file: stat() first so that a FIFO or device is never opened (opening a FIFO
// blocks), then read with a size cap (files in /proc report size 0). Throws SceneError
std::string read_scene_text(const std::string& path);

}  // namespace chainmail
