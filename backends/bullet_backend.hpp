// Bullet rigid-torus backend: every ring one rigid body whose collision shape is a compound of
// capsules (core/capsule_torus.hpp).
#pragma once

#include "backends/backend.hpp"
#include "core/capsule_torus.hpp"

namespace chainmail {

BackendInfo bullet_backend_info();

}  // namespace chainmail
