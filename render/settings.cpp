#include "render/settings.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace chainmail::render {
namespace {

struct Material {
  const char* name;
  float r, g, b;
};
constexpr Material kMaterials[] = {
    {"steel", 0.62f, 0.64f, 0.67f},   {"silver", 0.86f, 0.87f, 0.89f},
    {"gold", 1.0f, 0.77f, 0.34f},     {"copper", 0.95f, 0.55f, 0.38f},
    {"brass", 0.88f, 0.74f, 0.42f},   {"bronze", 0.76f, 0.52f, 0.31f},
    {"titanium", 0.56f, 0.54f, 0.51f}};
// index = the cloth shader's u_mode
constexpr const char* kClothShaders[] = {"blinn_phong", "texture", "bump", "displacement",
                                         "mirror"};
static_assert(std::string_view(kClothShaders[kDisplacementMode]) == "displacement");

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

}  // namespace

ResolvedSettings resolve_settings(const RenderSettings& settings) {
  ResolvedSettings resolved;
  const auto material =
      std::find_if(std::begin(kMaterials), std::end(kMaterials),
                   [&](const Material& m) { return settings.material == m.name; });
  if (material == std::end(kMaterials)) {
    throw RenderError("render: unknown material '" + settings.material + "' (" +
                      join(material_names()) + ")");
  }
  resolved.material = Eigen::Vector3f(material->r, material->g, material->b);
  const auto cloth =
      std::find(std::begin(kClothShaders), std::end(kClothShaders), settings.cloth_shader);
  if (cloth == std::end(kClothShaders)) {
    throw RenderError("render: unknown cloth shader '" + settings.cloth_shader + "' (" +
                      join(cloth_shader_names()) + ")");
  }
  resolved.cloth_mode = static_cast<int>(cloth - std::begin(kClothShaders));
  if (!(settings.lod_scale >= 0.0) || !std::isfinite(settings.lod_scale)) {
    throw RenderError("render: lod_scale must be a finite number >= 0");
  }
  if (settings.width < 1 || settings.height < 1 || settings.width > 16384 ||
      settings.height > 16384) {
    throw RenderError("render: image size " + std::to_string(settings.width) + "x" +
                      std::to_string(settings.height) + " out of range");
  }
  return resolved;
}

std::vector<std::string> material_names() {
  std::vector<std::string> names;
  for (const Material& m : kMaterials) names.emplace_back(m.name);
  return names;
}

std::vector<std::string> cloth_shader_names() {
  return {std::begin(kClothShaders), std::end(kClothShaders)};
}

}  // namespace chainmail::render
