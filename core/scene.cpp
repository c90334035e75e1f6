#include "core/scene.hpp"

namespace chainmail {

const char* to_string(WeaveType type) {
  switch (type) {
    case WeaveType::chain:
      return "chain";
    case WeaveType::four_in_one:
      return "4in1";
    case WeaveType::grid:
      return "grid";
  }
  return "?";
}

const char* to_string(SheetPlane plane) {
  switch (plane) {
    case SheetPlane::xz:
      return "xz";
    case SheetPlane::xy:
      return "xy";
    case SheetPlane::yz:
      return "yz";
    case SheetPlane::yx:
      return "yx";
  }
  return "?";
}

const char* to_string(Collider::Type type) {
  switch (type) {
    case Collider::Type::plane:
      return "plane";
    case Collider::Type::sphere:
      return "sphere";
    case Collider::Type::box:
      return "box";
    case Collider::Type::cylinder:
      return "cylinder";
  }
  return "?";
}

}  // namespace chainmail
