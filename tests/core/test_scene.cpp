#include <gtest/gtest.h>

#include <string>

#include "core/scene.hpp"

namespace chainmail {
namespace {

// the names are the scene file's words: the reader parses them, the writer and tables print them
TEST(SceneNames, EnumsPrintAsTheSceneFileSpellsThem) {
  EXPECT_EQ(std::string(to_string(WeaveType::chain)), "chain");
  EXPECT_EQ(std::string(to_string(WeaveType::four_in_one)), "4in1");
  EXPECT_EQ(std::string(to_string(WeaveType::grid)), "grid");
  EXPECT_EQ(std::string(to_string(SheetPlane::xz)), "xz");
  EXPECT_EQ(std::string(to_string(SheetPlane::xy)), "xy");
  EXPECT_EQ(std::string(to_string(SheetPlane::yz)), "yz");
  EXPECT_EQ(std::string(to_string(SheetPlane::yx)), "yx");
  EXPECT_EQ(std::string(to_string(Collider::Type::plane)), "plane");
  EXPECT_EQ(std::string(to_string(Collider::Type::sphere)), "sphere");
  EXPECT_EQ(std::string(to_string(Collider::Type::box)), "box");
  EXPECT_EQ(std::string(to_string(Collider::Type::cylinder)), "cylinder");
}

// a scene built in code (no file) describes the same default ring a file without "ring" gets
TEST(SceneDefaults, BuiltSceneHasTheFileDefaults) {
  const Scene scene;
  EXPECT_DOUBLE_EQ(scene.ring.wire_diameter(), 0.0016);
  EXPECT_DOUBLE_EQ(scene.ring.inner_diameter(), 0.008);
  EXPECT_EQ(scene.ring.density, 7850.0);
  EXPECT_EQ(scene.ring_inner_diameter, 0.0);  // not given
  EXPECT_TRUE(scene.camera.automatic);
  EXPECT_TRUE(scene.backends.empty());
}

}  // namespace
}  // namespace chainmail
