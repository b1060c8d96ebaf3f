#include "libbead/explain/model_series.h"

#include <algorithm>
#include <memory>

#include "libbead/series/interpolate.h"

namespace bead::explain {

SeriesData ModelSeries(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                       const model::TransferFunction& tf, const std::string& y_unit) {
  SeriesData d;
  d.t = t;
  d.u = u;
  d.y = y;
  d.y_unit = y_unit;
  const std::size_t n = t.size();
  const double gap = 5.0 * (n < 2 ? 1.0 : MedianStep(t));
  // Segments between stops; the model runs from rest in each.
  d.segment_time_s.assign(n, 0.0);
  d.base.assign(n, 0.0);
  std::size_t start = 0;
  for (std::size_t i = 0; i <= n; ++i) {
    if (i < n && (i == start || t[i] - t[i - 1] <= gap)) {
      d.segment_time_s[i] = t[i] - t[start];
      continue;
    }
    const std::vector<double> ts(t.begin() + static_cast<long>(start), t.begin() + static_cast<long>(i));
    const std::vector<double> us(u.begin() + static_cast<long>(start), u.begin() + static_cast<long>(i));
    const std::vector<double> ys = model::Simulate(tf, ts, us);
    std::copy(ys.begin(), ys.end(), d.base.begin() + static_cast<long>(start));
    if (i < n) {
      start = i;
      d.segment_time_s[i] = 0.0;
    }
  }
  // A delayed input: the same simulation read earlier (the model is time
  // invariant, so delaying its input delays its output).
  auto times = std::make_shared<std::vector<double>>(t);
  auto base = std::make_shared<std::vector<double>>(d.base);
  d.base_delayed = [times, base](const std::vector<double>& extra) {
    std::vector<double> out(times->size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = InterpolateLinear(*times, *base, (*times)[i] - extra[i]);
    return out;
  };
  return d;
}

}  // namespace bead::explain
