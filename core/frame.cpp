#include "core/frame.hpp"

#include <cstring>

namespace chainmail {
namespace {

std::uint64_t fnv1a(const double* data, long count, std::uint64_t hash) {
  for (long k = 0; k < count; ++k) {
    std::uint64_t bits;
    std::memcpy(&bits, &data[k], sizeof bits);
    for (int byte = 0; byte < 8; ++byte) {
      hash ^= (bits >> (8 * byte)) & 0xffu;
      hash *= 0x100000001b3ull;
    }
  }
  return hash;
}

}  // namespace

std::uint64_t frame_hash(const RingFrame& frame) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  hash = fnv1a(frame.position.data(), frame.position.size(), hash);
  hash = fnv1a(frame.orientation.data(), frame.orientation.size(), hash);
  return hash;
}

}  // namespace chainmail
