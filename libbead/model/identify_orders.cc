// The structures identify knows by name, and the thesis' order table
// (identify.h).
#include <algorithm>
#include <cmath>

#include "libbead/core/error.h"
#include "libbead/model/identify.h"

namespace bead::model {

void SetStructure(const std::string& name, IdentifyOptions& o) {
  if (name == "tf") return;
  struct Form {
    const char* name;
    int poles, zeros;
  };
  static const Form forms[] = {{"P1D", 1, 0},  {"P1DZ", 1, 1}, {"P2D", 2, 0},
                               {"P2DZ", 2, 1}, {"P3D", 3, 0},  {"P3DZ", 3, 1}};
  for (const Form& f : forms)
    if (name == f.name) {
      o.poles = f.poles;
      o.zeros = f.zeros;
      o.real_poles = true;
      return;
    }
  throw Error("the structure must be tf, P1D, P1DZ, P2D, P2DZ, P3D or P3DZ, got '" + name + "'");
}

std::vector<OrderRow> OrderTable(const std::vector<double>& t, const std::vector<double>& u,
                                 const std::vector<double>& y, const std::vector<double>& tv,
                                 const std::vector<double>& uv, const std::vector<double>& yv, IdentifyOptions o,
                                 const std::vector<Segment>& segments, const std::vector<Segment>& validation_segments,
                                 const std::function<void(int done, int total)>& progress) {
  std::vector<OrderRow> rows;
  constexpr int kOrders = 8;
  for (int p = 1; p <= 3; ++p)
    for (int z = 0; z <= std::min(p, 2); ++z) {  // thesis Table 3: (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2)
      if (progress) progress(static_cast<int>(rows.size()), kOrders);
      o.poles = p;
      o.zeros = z;
      const IdentifiedModel mdl = IdentifyTransferFunction(t, u, y, o, segments);
      rows.push_back({p, z, mdl.ok ? mdl.fit_percent : NAN,
                      mdl.ok ? ValidateFitPercent(mdl.tf, mdl.offset, tv, uv, yv, validation_segments) : NAN,
                      mdl.ok ? mdl.criteria.aicc : NAN, mdl.ok ? mdl.tf.delay_s : NAN, mdl.ok});
    }
  return rows;
}

}  // namespace bead::model
