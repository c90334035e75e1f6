// Rendering a run's sampled frames side by side into images/ (and compare.mp4 when ffmpeg exists).
#pragma once

#include <functional>
#include <string>

#include "bench/harness/run.hpp"

namespace chainmail {

// a writer for OutputOptions::render; creating it checks that GL and the shaders are available
// (throws SceneError-like errors that the command line maps to exit status 2)
// (`cloth_shader`, `material`: empty for the defaults, texture and steel; `last_only`: one image,
// of the last sample). It draws from the runs' frame streams (RunOptions::keep_stream).
std::function<void(const SceneRun&, const std::string&)> make_render_writer(
    const std::string& cloth_shader, const std::string& material = "", bool last_only = false);

}  // namespace chainmail
