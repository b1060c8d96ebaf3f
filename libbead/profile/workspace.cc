#include "libbead/profile/workspace.h"

namespace bead {

void ProfileWorkspace::Reserve(std::size_t points) {
  for (auto* v : {&x, &z, &s, &h}) v->resize(points);
  scratch.resize(4 * points + 256);  // median samples (padded to 8), residuals, triples
  for (auto* v : {&map, &spikes}) v->resize(points);
  kept_before.resize(points / 8 + 2);
}

}  // namespace bead
