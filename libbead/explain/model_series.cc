#include "libbead/explain/model_series.h"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <memory>

#include "libbead/model/identify.h"
#include "libbead/model/lti_response.h"
#include "libbead/series/interpolate.h"

namespace bead::explain {
SeriesData ModelSeries(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                       const model::TransferFunction& tf, double offset, const std::vector<Segment>& segments_in,
                       const std::string& y_unit, const std::vector<MoreInput>& more) {
  const std::vector<Segment> segments = segments_in.empty() ? WholeRecord(t.size()) : segments_in;
  // Each stretch from steady state at its first input; its initial state
  // is refitted in the loop (SeriesData::initial), not here, where it would
  // take up part of whatever the model lacks.
  const std::vector<double> main = model::Predict(tf, offset, t, u, {}, segments);
  std::vector<std::vector<double>> parts;
  for (const MoreInput& m : more) parts.push_back(model::Predict(m.tf, 0.0, t, m.u, {}, segments));
  const auto basis = model::FilterBasis(tf.Monic().den, tf.delay_s, t, u, segments);
  // Every input's free responses: initial-state columns for the stretches
  // whose start is unknown (not where the process started: that one starts
  // from rest).
  std::vector<model::StateResponses> free = {model::ComputeStateResponses(tf.Monic().den, tf.delay_s, t, u, segments)};
  for (const MoreInput& m : more)
    free.push_back(model::ComputeStateResponses(m.tf.Monic().den, m.tf.delay_s, t, m.u, segments));
  SeriesData d;
  d.y_unit = y_unit;
  d.dynamics.resize(basis.size());
  for (const MoreInput& m : more) d.input_parts.push_back({m.name, {}});
  std::vector<double> main_kept;
  auto all_finite = [&](std::size_t i) {
    if (!std::isfinite(y[i]) || !std::isfinite(main[i])) return false;
    for (const auto& p : parts)
      if (!std::isfinite(p[i])) return false;
    return true;
  };
  for (std::size_t si = 0; si < segments.size(); ++si) {
    const Segment& s = segments[si];
    const std::size_t first = d.initial.size();
    if (!s.process_starts)
      for (const auto& f : free)
        d.initial.resize(d.initial.size() + f.free.size(), std::vector<double>(d.t.size(), 0.0));
    for (std::size_t i = s.begin; i < s.end; ++i) {
      if (!all_finite(i)) continue;
      d.t.push_back(t[i]);
      d.u.push_back(u[i]);
      d.y.push_back(y[i]);
      main_kept.push_back(main[i]);
      double b = main[i];
      for (std::size_t k = 0; k < parts.size(); ++k) b += parts[k][i], d.input_parts[k].values.push_back(parts[k][i]);
      d.base.push_back(b);
      d.segment_time_s.push_back(t[i] - t[s.begin]);
      for (std::size_t k = 0; k < basis.size(); ++k) d.dynamics[k].push_back(basis[k][i]);
      std::size_t c = 0;
      for (; c < first; ++c) d.initial[c].push_back(0.0);
      if (!s.process_starts)
        for (const auto& f : free)
          for (const auto& col : f.free) d.initial[c++].push_back(col[i]);
    }
  }
  // A delayed input: the first input's part read earlier (the model is
  // time invariant, so delaying its input delays its output), the others'
  // as they are.
  auto times = std::make_shared<std::vector<double>>(d.t);
  auto kept = std::make_shared<std::vector<double>>(main_kept);
  auto rest = std::make_shared<std::vector<double>>(d.base);
  for (std::size_t i = 0; i < rest->size(); ++i) (*rest)[i] -= main_kept[i];
  d.base_delayed = [times, kept, rest](const std::vector<double>& extra) {
    std::vector<double> out(times->size());
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = InterpolateLinear(*times, *kept, (*times)[i] - extra[i]) + (*rest)[i];
    return out;
  };
  return d;
}

}  // namespace bead::explain
