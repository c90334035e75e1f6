// The largest centre distance of two linked rings over their relative orientation
// (core/plausible/link_distance.hpp), as CSV on stdout: one row per orientation on a 5-degree grid,
// for the default ring (wire diameter 1.6 mm, inner diameter 8 mm) or `--aspect AR` (inner diameter
// / wire diameter). bench/plot_link_distance.py plots it; scripts/link_distance.sh runs both.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <string>

#include "core/plausible/link_distance.hpp"

namespace {

// the aspect ratio from `--aspect AR`, the default ring's without arguments; 0 on bad input
double aspect_from_arguments(int argc, char** argv) {
  if (argc == 1) return chainmail::RingGeometry{}.aspect_ratio();
  if (argc != 3 || std::strcmp(argv[1], "--aspect") != 0) return 0.0;
  char* end = nullptr;
  const double aspect = std::strtod(argv[2], &end);
  return *end == '\0' && aspect >= 2.0 && aspect <= 100.0 ? aspect : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  const double aspect = aspect_from_arguments(argc, argv);
  if (aspect == 0.0) {
    std::fprintf(stderr,
                 "chainmail_link_table: usage: chainmail_link_table [--aspect AR], "
                 "AR in [2, 100]\n");
    return 2;
  }
  const chainmail::RingGeometry defaults;
  const chainmail::RingGeometry ring = chainmail::RingGeometry::from_diameters(
      defaults.wire_diameter(), aspect * defaults.wire_diameter(), defaults.density);
  const double degree = std::numbers::pi / 180.0;
  std::printf("aspect_ratio,tilt_first_deg,tilt_second_deg,twist_deg,max_distance_over_id\n");
  for (int first = 0; first <= 90; first += 5) {
    for (int second = 0; second <= 90; second += 5) {
      for (int twist = 0; twist <= 180; twist += 5) {
        const chainmail::LinkOrientation o{first * degree, second * degree, twist * degree};
        const double d = chainmail::max_link_distance(o, ring) / ring.inner_diameter();
        std::printf("%g,%d,%d,%d,%.9f\n", aspect, first, second, twist, d);
      }
    }
  }
  return 0;
}
