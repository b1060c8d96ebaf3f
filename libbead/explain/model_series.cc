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
                       const std::string& y_unit) {
  const std::vector<Segment> segments = segments_in.empty() ? WholeRecord(t.size()) : segments_in;
  // Each stretch from steady state at its first input; its initial state
  // is refitted in the loop (SeriesData::initial), not here, where it would
  // take up part of whatever the model lacks.
  const std::vector<double> base = model::Predict(tf, offset, t, u, {}, segments);
  std::vector<double> den = tf.den;
  for (double& c : den) c /= tf.den[0];
  const auto basis = model::FilterBasis(den, tf.delay_s, t, u, segments);
  const model::StateResponses free = model::ComputeStateResponses(den, tf.delay_s, t, u, segments);
  const std::size_t n = static_cast<std::size_t>(free.n);
  SeriesData d;
  d.y_unit = y_unit;
  d.dynamics.resize(basis.size());
  // Initial-state columns for the stretches whose start is unknown (not
  // where the process started: that one starts from rest).
  std::vector<std::size_t> first_column(segments.size(), SIZE_MAX);
  std::size_t columns = 0;
  for (std::size_t si = 0; si < segments.size(); ++si)
    if (!segments[si].process_starts) first_column[si] = columns, columns += n;
  d.initial.resize(columns);
  for (std::size_t si = 0; si < segments.size(); ++si) {
    const Segment& s = segments[si];
    for (std::size_t i = s.begin; i < s.end; ++i) {
      if (!std::isfinite(y[i]) || !std::isfinite(base[i])) continue;
      d.t.push_back(t[i]);
      d.u.push_back(u[i]);
      d.y.push_back(y[i]);
      d.base.push_back(base[i]);
      d.segment_time_s.push_back(t[i] - t[s.begin]);
      for (std::size_t k = 0; k < basis.size(); ++k) d.dynamics[k].push_back(basis[k][i]);
      for (std::size_t c = 0; c < d.initial.size(); ++c)
        d.initial[c].push_back(c >= first_column[si] && c < first_column[si] + n ? free.free[c - first_column[si]][i]
                                                                                 : 0.0);
    }
  }
  // A delayed input: the same prediction read earlier (the model is time
  // invariant, so delaying its input delays its output).
  auto times = std::make_shared<std::vector<double>>(d.t);
  auto kept = std::make_shared<std::vector<double>>(d.base);
  d.base_delayed = [times, kept](const std::vector<double>& extra) {
    std::vector<double> out(times->size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = InterpolateLinear(*times, *kept, (*times)[i] - extra[i]);
    return out;
  };
  return d;
}

}  // namespace bead::explain
