#include "libbead/profile/workspace.h"

namespace bead {

void ProfileWorkspace::Reserve(std::size_t points) {
  for (auto* v : {&left_x, &left_z, &right_x, &right_z, &x, &s, &h}) v->resize(points);
  scratch.reserve(points);
  order.resize(points);
  keep.resize(points);
}

}  // namespace bead
