#include "libbead/model/predict.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "libbead/model/fit_metrics.h"
#include "libbead/model/lti_response.h"
#include "libbead/series/interpolate.h"

namespace bead::model {

std::vector<double> Predict(const TransferFunction& tf, double offset, const std::vector<double>& t,
                            const std::vector<double>& u, const std::vector<double>& y,
                            const std::vector<Segment>& segments_in) {
  tf.Validate();
  const std::vector<Segment> segments = segments_in.empty() ? WholeRecord(t.size()) : segments_in;
  const TransferFunction monic = tf.Monic();
  const std::vector<double>&den = monic.den, &num = monic.num;
  const int n = static_cast<int>(den.size()) - 1;
  std::vector<double> out(t.size(), std::numeric_limits<double>::quiet_NaN());
  if (n == 0) {
    for (const Segment& s : segments)
      for (std::size_t i = s.begin; i < s.end; ++i)
        out[i] = offset + num.back() * InterpolateLinear(t, u, t[i] - tf.delay_s);
    return out;
  }
  const int m = static_cast<int>(num.size()) - 1;
  auto forced = [&](const StateResponses& r, std::size_t i) {
    double v = 0;
    for (int k = 0; k <= m; ++k) {
      const double c = num[static_cast<std::size_t>(m - k)];
      if (k < n) {
        v += c * r.state[static_cast<std::size_t>(k)][i];
      } else {
        double w = r.delayed[i];
        for (int j = 0; j < n; ++j) w -= den[static_cast<std::size_t>(n - j)] * r.state[static_cast<std::size_t>(j)][i];
        v += c * w;
      }
    }
    return v;
  };
  if (y.empty()) {
    // Each segment in steady state at its first input: the response to the
    // input less that level, from rest, plus the level's steady output.
    // A segment where the process started: at rest at its first sample,
    // driven from then by the delayed input (which may date from before the
    // start: the record holds it).
    for (const Segment& s : segments) {
      if (s.begin >= s.end) continue;
      const double level = s.process_starts ? 0.0 : u[s.begin];
      std::vector<double> w(u.size(), 0.0);
      for (std::size_t i = s.process_starts ? 0 : s.begin; i < u.size(); ++i) w[i] = u[i] - level;
      const StateResponses r = ComputeStateResponses(den, tf.delay_s, t, w, {s});
      for (std::size_t i = s.begin; i < s.end; ++i) out[i] = offset + tf.DcGain() * level + forced(r, i);
    }
    return out;
  }
  // The initial states fitted to y by least squares, the model fixed.
  const StateResponses r = ComputeStateResponses(den, tf.delay_s, t, u, segments);
  for (const Segment& s : segments) {
    std::vector<std::size_t> rows;
    for (std::size_t i = s.begin; i < s.end; ++i)
      if (std::isfinite(y[i])) rows.push_back(i);
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n);
    if (!s.process_starts && rows.size() > static_cast<std::size_t>(2 * n)) {
      Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), n);
      Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
      for (std::size_t k = 0; k < rows.size(); ++k) {
        for (int j = 0; j < n; ++j) a(static_cast<Eigen::Index>(k), j) = r.free[static_cast<std::size_t>(j)][rows[k]];
        b(static_cast<Eigen::Index>(k)) = y[rows[k]] - offset - forced(r, rows[k]);
      }
      const Eigen::VectorXd sol = a.colPivHouseholderQr().solve(b);
      if (sol.allFinite()) x0 = sol;
    }
    for (std::size_t i = s.begin; i < s.end; ++i) {
      double v = offset + forced(r, i);
      for (int j = 0; j < n; ++j) v += x0(j) * r.free[static_cast<std::size_t>(j)][i];
      out[i] = v;
    }
  }
  return out;
}

double ValidateFitPercent(const TransferFunction& tf, double offset, const std::vector<double>& t,
                          const std::vector<double>& u, const std::vector<double>& y,
                          const std::vector<Segment>& segments) {
  return FitPercent(y, Predict(tf, offset, t, u, y, segments));
}

}  // namespace bead::model
