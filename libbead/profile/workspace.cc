#include "libbead/profile/workspace.h"

namespace bead {

void ProfileWorkspace::Reserve(std::size_t points) {
  for (auto* v : {&left_x, &left_z, &right_x, &right_z, &scratch, &x, &s, &h}) v->reserve(points);
  order.reserve(points);
  keep.reserve(points);
}

}  // namespace bead
