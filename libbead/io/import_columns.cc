#include "libbead/io/import_columns.h"

#include <cmath>

#include "libbead/core/error.h"

namespace bead {

void CheckImportColumns(const std::string& path, const ImportColumns& c, bool profile_required) {
  if (!(std::isfinite(c.time_scale) && c.time_scale > 0.0))
    throw Error(Located(path, "", "the time scale must be a positive number"));
  for (const auto* name : {&c.time, &c.x, &c.z})
    if (name->empty()) throw Error(Located(path, "", "the time, x and z columns must all be named"));
  if (profile_required && c.profile.empty())
    throw Error(Located(path, "", "name the column of the profile id (--profile-column)"));
  const bool placed = !c.path.empty() || c.head_speed_mm_s > 0.0;
  if (!c.part() && (placed || !c.frame_z.empty() || !c.frame_x.empty()))
    throw Error(Located(path, "", "a part's columns need the layer's (--layer-column)"));
  if (c.part() && !placed)
    throw Error(Located(path, "",
                        "a part scan needs each profile's place along the toolpath: --path-column, or "
                        "--head-speed-mm-s to place it at the head's speed"));
  if (c.part() && !c.path.empty() && c.head_speed_mm_s > 0.0)
    throw Error(Located(path, "", "give --path-column or --head-speed-mm-s, not both"));
}

}  // namespace bead
