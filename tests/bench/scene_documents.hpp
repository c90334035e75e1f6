// Scene documents shared by the scene-file tests.
#pragma once

#include <nlohmann/json.hpp>

namespace chainmail::test {

// the smallest scene the loader accepts: a 4 x 5 sheet for 0.1 s
inline nlohmann::json minimal_scene() {
  return nlohmann::json{
      {"name", "t"}, {"weave", {{"type", "4in1"}, {"rows", 4}, {"cols", 5}}}, {"duration", 0.1}};
}

}  // namespace chainmail::test
