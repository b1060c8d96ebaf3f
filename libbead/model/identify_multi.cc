#include "libbead/model/identify_multi.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "libbead/model/predict.h"

namespace bead::model {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The samples scored: inside the segments, y and every part finite, past
// the first `skip_s` of a stretch whose start is unknown (as identify.cc).
std::vector<std::size_t> ScoredRows(const std::vector<double>& t, const std::vector<double>& y,
                                    const std::vector<std::vector<double>>& parts, const std::vector<Segment>& segments,
                                    double skip_s) {
  std::vector<std::size_t> rows;
  for (const Segment& s : segments)
    for (std::size_t i = s.begin; i < std::min(s.end, t.size()); ++i) {
      if (!std::isfinite(y[i]) || (!s.process_starts && t[i] < t[s.begin] + skip_s)) continue;
      if (std::all_of(parts.begin(), parts.end(), [i](const std::vector<double>& p) { return std::isfinite(p[i]); }))
        rows.push_back(i);
    }
  return rows;
}

double Sse(const std::vector<double>& y, const std::vector<std::vector<double>>& parts, double offset,
           const std::vector<std::size_t>& rows) {
  double s = 0;
  for (std::size_t i : rows) {
    double e = y[i] - offset;
    for (const auto& p : parts) e -= p[i];
    s += e * e;
  }
  return s;
}

// The largest |correlation| over the rows between two inputs.
double MaxInputCorrelation(const std::vector<std::vector<double>>& parts, const std::vector<std::size_t>& rows) {
  double worst = 0;
  const double n = static_cast<double>(rows.size());
  for (std::size_t a = 0; a < parts.size(); ++a)
    for (std::size_t b = a + 1; b < parts.size(); ++b) {
      double ma = 0, mb = 0;
      for (std::size_t i : rows) ma += parts[a][i] / n, mb += parts[b][i] / n;
      double saa = 0, sbb = 0, sab = 0;
      for (std::size_t i : rows) {
        const double x = parts[a][i] - ma, z = parts[b][i] - mb;
        saa += x * x, sbb += z * z, sab += x * z;
      }
      if (saa > 0 && sbb > 0) worst = std::max(worst, std::abs(sab / std::sqrt(saa * sbb)));
    }
  return worst;
}

}  // namespace

namespace {

// Each input's part of the prediction (its free response included), its
// fit's offset (their sum is the operating point) and the scored rows.
struct Parts {
  std::vector<std::vector<double>> part;
  std::vector<double> offset;
  std::vector<std::size_t> rows;
};

// The sweeps: each input's model identified on the output less the other
// inputs' current parts, until a sweep lowers the error by less than a
// part in 10^5. False (out.reason said) when an input's fit fails.
bool Backfit(const std::vector<double>& t, const std::vector<std::vector<double>>& u, const std::vector<double>& y,
             const std::vector<IdentifyOptions>& options, const std::vector<Segment>& segments, double skip,
             int max_sweeps, MultiInputModel& out, Parts& p) {
  const std::size_t k = u.size();
  p.part.assign(k, std::vector<double>(t.size(), 0.0));
  p.offset.assign(k, 0.0);
  out.inputs.resize(k);
  double previous = std::numeric_limits<double>::infinity();
  for (int sweep = 1; sweep <= max_sweeps; ++sweep) {
    for (std::size_t i = 0; i < k; ++i) {
      std::vector<double> target(y);
      for (std::size_t j = 0; j < k; ++j)
        if (j != i)
          for (std::size_t r = 0; r < t.size(); ++r) target[r] -= p.part[j][r] + p.offset[j];
      IdentifiedModel m = IdentifyTransferFunction(t, u[i], target, options[i], segments);
      if (!m.ok) {
        out.reason = "input " + std::to_string(i + 1) + ": " + m.reason;
        return false;
      }
      p.offset[i] = m.offset;
      for (std::size_t r = 0; r < t.size(); ++r) p.part[i][r] = m.prediction[r] - m.offset;
      out.inputs[i] = std::move(m);
    }
    double offset = 0;
    for (double c : p.offset) offset += c;
    p.rows = ScoredRows(t, y, p.part, segments, skip);
    const double sse = Sse(y, p.part, offset, p.rows);
    out.sweeps = sweep;
    if (previous - sse <= 1e-5 * sse || k == 1) {
      out.converged = true;
      break;
    }
    previous = sse;
  }
  return true;
}

// The whole model's prediction, fit, parameter count and criteria, each
// input's part and level, and what to say of them.
void Summarise(const std::vector<double>& t, const std::vector<std::vector<double>>& u, const std::vector<double>& y,
               const std::vector<IdentifyOptions>& options, const std::vector<Segment>& segments, const Parts& p,
               MultiInputModel& out) {
  out.offset = 0;
  for (double c : p.offset) out.offset += c;
  out.prediction.assign(t.size(), kNaN);
  for (const Segment& s : segments)
    for (std::size_t r = s.begin; r < std::min(s.end, t.size()); ++r) {
      double v = out.offset;
      for (const auto& part : p.part) v += part[r];
      out.prediction[r] = v;
    }
  std::vector<double> yr, pr, residual;
  for (std::size_t r : p.rows) {
    yr.push_back(y[r]), pr.push_back(out.prediction[r]);
    residual.push_back(y[r] - out.prediction[r]);
  }
  out.fit_percent = FitPercent(yr, pr);
  out.fitted_samples = p.rows.size();
  out.parameters = 1;  // the one operating point
  for (std::size_t i = 0; i < out.inputs.size(); ++i) {
    IdentifiedModel& m = out.inputs[i];
    m.parameters -= options[0].estimate_offset ? 1 : 0;
    out.parameters += m.parameters;
    m.prediction = p.part[i];
    m.offset = 0.0;
    m.output_level = m.tf.DcGain() * m.input_level;
  }
  out.criteria = CriteriaFromResiduals(residual, out.parameters);
  out.max_input_correlation = MaxInputCorrelation(u, p.rows);
  if (out.max_input_correlation > 0.9) {
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "two inputs correlate at %.3f over the fitted samples: the data cannot tell their effects apart; "
                  "their gains trade against each other",
                  out.max_input_correlation);
    out.note = buf;
  }
  if (!out.converged) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "backfitting stopped after %d sweeps before the error settled", out.sweeps);
    out.note += (out.note.empty() ? "" : "; ") + std::string(buf);
  }
}

}  // namespace

MultiInputModel IdentifyMultiInput(const std::vector<double>& t, const std::vector<std::vector<double>>& u,
                                   const std::vector<double>& y, const std::vector<IdentifyOptions>& options,
                                   const std::vector<Segment>& segments_in, int max_sweeps) {
  MultiInputModel out;
  if (u.empty() || options.size() != u.size()) {
    out.reason = "need at least one input and options for each";
    return out;
  }
  const std::vector<Segment> segments = segments_in.empty() ? WholeRecord(t.size()) : segments_in;
  double skip = 0;
  for (const IdentifyOptions& o : options)
    if (options[0].estimate_initial_state) skip = std::max(skip, o.delay_s ? *o.delay_s : o.max_delay_s);
  Parts p;
  if (!Backfit(t, u, y, options, segments, skip, max_sweeps, out, p)) return out;
  if (p.rows.size() < 2) {
    out.reason = "too few samples left to score the model";
    return out;
  }
  Summarise(t, u, y, options, segments, p, out);
  out.ok = true;
  return out;
}

std::vector<double> PredictMultiInput(const std::vector<TransferFunction>& tfs, double offset,
                                      const std::vector<double>& t, const std::vector<std::vector<double>>& u,
                                      const std::vector<double>& y, const std::vector<Segment>& segments) {
  const std::size_t k = tfs.size();
  std::vector<std::vector<double>> parts(k);
  for (std::size_t i = 0; i < k; ++i) parts[i] = Predict(tfs[i], 0.0, t, u[i], {}, segments);
  // With y: each input's initial state fitted to what the others leave,
  // in turn (three passes: the states' parts barely overlap).
  for (int pass = 0; !y.empty() && pass < 3; ++pass)
    for (std::size_t i = 0; i < k; ++i) {
      std::vector<double> target(y);
      for (std::size_t r = 0; r < t.size(); ++r) {
        target[r] -= offset;
        for (std::size_t j = 0; j < k; ++j)
          if (j != i) target[r] -= parts[j][r];
      }
      parts[i] = Predict(tfs[i], 0.0, t, u[i], target, segments);
    }
  std::vector<double> out(t.size(), kNaN);
  for (std::size_t r = 0; r < t.size(); ++r) {
    double v = offset;
    for (const auto& p : parts) v += p[r];
    out[r] = v;
  }
  return out;
}

}  // namespace bead::model
