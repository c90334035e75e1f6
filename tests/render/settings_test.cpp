// What the renderer's setting names stand for, checked before any GL work.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "render/settings.hpp"

namespace chainmail::render {
namespace {

// the message of the RenderError that resolve_settings throws, or "" when it accepts them
std::string refusal(const RenderSettings& settings) {
  try {
    resolve_settings(settings);
  } catch (const RenderError& error) {
    return error.what();
  }
  return "";
}

TEST(RenderSettingsCheck, NamesResolveToTheirMaterialAndMode) {
  RenderSettings settings;
  EXPECT_EQ(resolve_settings(settings).material, Eigen::Vector3f(0.62f, 0.64f, 0.67f));  // steel
  settings.material = "gold";
  EXPECT_EQ(resolve_settings(settings).material, Eigen::Vector3f(1.0f, 0.77f, 0.34f));
  // every listed name resolves, to distinct colours and to its index as the cloth mode
  std::vector<Eigen::Vector3f> colours;
  for (const std::string& name : material_names()) {
    settings.material = name;
    colours.push_back(resolve_settings(settings).material);
    for (size_t k = 0; k + 1 < colours.size(); ++k) EXPECT_NE(colours[k], colours.back()) << name;
  }
  const std::vector<std::string> shaders = cloth_shader_names();
  for (size_t mode = 0; mode < shaders.size(); ++mode) {
    settings.cloth_shader = shaders[mode];
    EXPECT_EQ(resolve_settings(settings).cloth_mode, static_cast<int>(mode)) << shaders[mode];
  }
  EXPECT_EQ(shaders.at(kDisplacementMode), "displacement");
}

TEST(RenderSettingsCheck, UnknownNamesAndBadNumbersAreRefusedWithTheReason) {
  RenderSettings settings;
  settings.material = "plutonium";
  EXPECT_NE(refusal(settings).find("unknown material 'plutonium' (steel, silver"),
            std::string::npos)
      << refusal(settings);
  settings = RenderSettings{};
  settings.cloth_shader = "velvet";
  EXPECT_NE(refusal(settings).find("unknown cloth shader 'velvet' (blinn_phong, texture"),
            std::string::npos)
      << refusal(settings);

  for (double scale :
       {-0.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    settings = RenderSettings{};
    settings.lod_scale = scale;
    EXPECT_NE(refusal(settings).find("lod_scale"), std::string::npos) << scale;
  }
  settings = RenderSettings{};
  settings.lod_scale = 0.0;
  EXPECT_EQ(refusal(settings), "");

  for (const auto& [w, h] : {std::pair{0, 10}, {10, 0}, {16385, 10}, {10, 16385}, {-1, -1}}) {
    settings = RenderSettings{};
    settings.width = w, settings.height = h;
    EXPECT_NE(refusal(settings).find("out of range"), std::string::npos) << w << "x" << h;
  }
  settings = RenderSettings{};
  settings.width = 16384, settings.height = 1;
  EXPECT_EQ(refusal(settings), "");
}

}  // namespace
}  // namespace chainmail::render
