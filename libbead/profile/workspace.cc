#include "libbead/profile/workspace.h"

namespace bead {

void ProfileWorkspace::Reserve(std::size_t points) {
  for (auto* v : {&x, &z, &s, &h, &hx}) v->resize(points);
  scratch.resize(2 * points + 128);  // median samples (padded to 8) and residuals
  for (auto* v : {&removed, &map, &spikes}) v->resize(points);
}

}  // namespace bead
