#include "libbead/explain/model_series.h"

#include <algorithm>
#include <memory>

namespace bead::explain {

double InterpolateAt(const std::vector<double>& t, const std::vector<double>& v, double x) {
  if (x <= t.front()) return v.front();
  if (x >= t.back()) return v.back();
  const auto it = std::upper_bound(t.begin(), t.end(), x);
  const auto i = static_cast<std::size_t>(it - t.begin());
  const double f = (x - t[i - 1]) / (t[i] - t[i - 1]);
  return v[i - 1] + f * (v[i] - v[i - 1]);
}

SeriesData ModelSeries(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                       const model::TransferFunction& tf, const std::string& y_unit) {
  SeriesData d;
  d.t = t;
  d.u = u;
  d.y = y;
  d.y_unit = y_unit;
  const std::size_t n = t.size();
  std::vector<double> dt;
  for (std::size_t i = 1; i < n; ++i) dt.push_back(t[i] - t[i - 1]);
  std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
  const double gap = 5.0 * (dt.empty() ? 1.0 : dt[dt.size() / 2]);
  // Segments between stops; the model runs from rest in each.
  d.segment_time_s.assign(n, 0.0);
  d.base.assign(n, 0.0);
  std::size_t start = 0;
  bool stopped = false;
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
      stopped = true;
      start = i;
      d.segment_time_s[i] = 0.0;
    }
  }
  (void)stopped;
  // A delayed input: the same simulation read earlier (the model is time
  // invariant, so delaying its input delays its output).
  auto times = std::make_shared<std::vector<double>>(t);
  auto base = std::make_shared<std::vector<double>>(d.base);
  d.base_delayed = [times, base](const std::vector<double>& extra) {
    std::vector<double> out(times->size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = InterpolateAt(*times, *base, (*times)[i] - extra[i]);
    return out;
  };
  return d;
}

}  // namespace bead::explain
