// What the names in RenderSettings stand for (ring materials, cloth shaders) and the checks made on
// the settings before any GL work, so that a bad setting fails before a context is made use of.
#pragma once

#include <Eigen/Core>

#include "render/types.hpp"

namespace chainmail::render {

// the cloth shader's u_mode for `displacement`: its mesh is subdivided
inline constexpr int kDisplacementMode = 3;
inline constexpr int kDisplacementSubdivisions = 4;

struct ResolvedSettings {
  Eigen::Vector3f material;  // linear RGB albedo of the rings
  int cloth_mode = 0;        // the cloth shader's u_mode: index in cloth_shader_names()
};

// throws RenderError: unknown material or cloth shader, lod_scale not finite or below 0, image
// size outside 1..16384
ResolvedSettings resolve_settings(const RenderSettings& settings);

// names accepted by RenderSettings::material and ::cloth_shader
std::vector<std::string> material_names();
std::vector<std::string> cloth_shader_names();

}  // namespace chainmail::render
