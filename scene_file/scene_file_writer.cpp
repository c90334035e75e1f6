// Scene files: the writer. The resolved scene has the reader's shape, key for key, so that reading
// it back gives the same scene and its hash keys cached reference runs.
#include <cstdint>

#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

json vec3(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}
json ring_cell(int row, int col) {
  return json::array({row, col});
}

// the inner diameter as given when it still gives this ring (2(c - a) can differ in the last bit)
double written_inner_diameter(const Scene& scene) {
  const RingGeometry& ring = scene.ring;
  const RingGeometry given =
      RingGeometry::from_diameters(ring.wire_diameter(), scene.ring_inner_diameter, ring.density);
  const bool same = scene.ring_inner_diameter > 0.0 && given.wire_radius == ring.wire_radius &&
                    given.centre_radius == ring.centre_radius;
  return same ? scene.ring_inner_diameter : ring.inner_diameter();
}

json ring_json(const Scene& scene) {
  return {{"wire_diameter", scene.ring.wire_diameter()},
          {"inner_diameter", written_inner_diameter(scene)},
          {"density", scene.ring.density},
          {"friction", scene.ring_friction}};
}

json weave_json(const WeaveSpec& weave) {
  json out = {{"type", to_string(weave.type)},
              {"rows", weave.rows},
              {"cols", weave.cols},
              {"plane", to_string(weave.plane)},
              {"center", vec3(weave.center)}};
  // a 4-in-1 sheet has its fixed rest layout: the reader refuses a spacing there
  if (weave.type != WeaveType::four_in_one) out["spacing"] = weave.spacing;
  return out;
}

json pin_json(const PinSpec& pin) {
  switch (pin.kind) {
    case PinSpec::Kind::ring:
      return {{"ring", ring_cell(pin.row, pin.col)}};
    case PinSpec::Kind::edge:
      return {{"edge", pin.which}};
    case PinSpec::Kind::corner:
      return {{"corner", pin.which}};
  }
  return json::object();
}

json collider_json(const Collider& collider) {
  json out = {{"type", to_string(collider.type)}, {"friction", collider.friction}};
  switch (collider.type) {
    case Collider::Type::plane: {
      // the normal as given when it still gives this plane (a built one may have only the unit)
      const bool given = collider.given_normal.normalized() == collider.normal;
      out["point"] = vec3(collider.center);
      out["normal"] = vec3(given ? collider.given_normal : collider.normal);
      break;
    }
    case Collider::Type::sphere:
      out["center"] = vec3(collider.center);
      out["radius"] = collider.radius;
      break;
    case Collider::Type::box:
      out["center"] = vec3(collider.center);
      out["half_extents"] = vec3(collider.half_extents);
      break;
    case Collider::Type::cylinder:
      out["center"] = vec3(collider.center);
      out["radius"] = collider.radius;
      out["half_height"] = collider.half_height;
      break;
  }
  return out;
}

json camera_json(const Camera& camera) {
  json out = {{"fov_deg", camera.fov_deg}};
  // an automatic camera has no position or target: giving either would fix it
  if (!camera.automatic) {
    out["position"] = vec3(camera.position);
    out["target"] = vec3(camera.target);
  }
  return out;
}

json stability_json(const StabilityBounds& bounds) {
  return {{"max_speed", bounds.max_speed},
          {"links_must_hold", bounds.links_must_hold},
          {"max_stretch", bounds.max_stretch},
          {"energy_growth", bounds.energy_growth}};
}

// a knob in the form it was written: integers as integers, booleans as true/false, strings (a
// choice's name) as themselves. A value of another kind (array, object, null) is kept only as its
// kind: written as null, which reads back as the same kind (backends/registry refuses it either
// way)
json knob_json(const KnobValue& knob) {
  switch (knob.kind) {
    case KnobValue::Kind::boolean:
      return knob.value != 0.0;
    case KnobValue::Kind::integer:
      if (knob.value >= 0.0 && knob.value < 0x1p64) return static_cast<std::uint64_t>(knob.value);
      if (knob.value < 0.0 && knob.value >= -0x1p63) return static_cast<std::int64_t>(knob.value);
      return knob.value;
    case KnobValue::Kind::number:
      return knob.value;
    case KnobValue::Kind::string:
      return knob.text;
    case KnobValue::Kind::other:
      return nullptr;
  }
  return nullptr;
}

json backends_json(const Scene& scene) {
  json out = json::object();
  for (const auto& [backend, section] : scene.backends) {
    json& knobs = out[backend] = json::object();
    for (const auto& [name, knob] : section) knobs[name] = knob_json(knob);
  }
  return out;
}

}  // namespace

json scene_to_json(const Scene& scene) {
  json out = {{"name", scene.name}, {"description", scene.description}};
  out["ring"] = ring_json(scene);
  out["weave"] = weave_json(scene.weave);
  json& pins = out["pins"] = json::array();
  for (const PinSpec& pin : scene.pins) pins.push_back(pin_json(pin));
  json& colliders = out["colliders"] = json::array();
  for (const Collider& collider : scene.colliders) colliders.push_back(collider_json(collider));
  if (scene.support) {
    out["support"] = {{"center", vec3(scene.support->center)}, {"radius", scene.support->radius}};
  }
  // loads only when there are any: the key is optional and has no default to fill in
  if (!scene.loads.empty()) {
    json& loads = out["loads"] = json::array();
    for (const Load& load : scene.loads) {
      loads.push_back({{"ring", ring_cell(load.row, load.col)}, {"mass_factor", load.mass_factor}});
    }
  }
  out["initial_velocity"] = vec3(scene.initial_velocity);
  out["gravity"] = vec3(scene.gravity);
  out["duration"] = scene.duration;
  out["sample_interval"] = scene.sample_interval;
  out["features"] = {{"self_contact", scene.self_contact}};
  out["output"] = {{"frames", scene.write_frames}};
  out["camera"] = camera_json(scene.camera);
  out["stability"] = stability_json(scene.stability);
  out["reference"] = scene.reference;
  out["reference_dt"] = scene.reference_dt;
  out["backends"] = backends_json(scene);
  return out;
}

}  // namespace chainmail
