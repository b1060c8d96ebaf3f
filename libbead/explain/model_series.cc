#include "libbead/explain/model_series.h"

#include <algorithm>
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
  const std::vector<double> base = model::Predict(tf, offset, t, u, y, segments);
  std::vector<double> den = tf.den;
  const auto basis = model::FilterBasis(den, tf.delay_s, t, u, segments);
  SeriesData d;
  d.y_unit = y_unit;
  d.dynamics.resize(basis.size());
  for (const Segment& s : segments)
    for (std::size_t i = s.begin; i < s.end; ++i) {
      if (!std::isfinite(y[i]) || !std::isfinite(base[i])) continue;
      d.t.push_back(t[i]);
      d.u.push_back(u[i]);
      d.y.push_back(y[i]);
      d.base.push_back(base[i]);
      d.segment_time_s.push_back(t[i] - t[s.begin]);
      for (std::size_t k = 0; k < basis.size(); ++k) d.dynamics[k].push_back(basis[k][i]);
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
