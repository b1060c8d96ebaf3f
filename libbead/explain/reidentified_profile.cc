#include "libbead/explain/reidentified_profile.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "libbead/explain/run_series.h"

namespace bead::explain {
namespace {

constexpr double kChi2_1_95 = 3.841;  // chi-squared, one degree of freedom, 95 %

struct Trial {
  double mean_square = INFINITY;  // over the fitted samples
  model::TransferFunction tf;     // the model identified there (the next trial's start)
};

// The flow aligned at `counts` and the model identified on it from `start`.
Trial IdentifiedAt(const Rig& rig, const MeasuredFlow& run, double counts, const model::TransferFunction& start,
                   std::size_t bin, model::IdentifyOptions o) {
  Rig aligned = rig;
  aligned.offset_counts = counts;
  const FlowResult flow =
      ComputeFlow(aligned, *run.profiles, *run.geometry, *run.log, {}, run.CorrectedArea(), run.CorrectedSigma());
  const BinnedFlow b = BinValidFlow(flow, bin);
  o.start = start;
  const model::IdentifiedModel m = model::IdentifyTransferFunction(b.t, b.u, b.y, o);
  Trial out;
  if (!m.ok) return out;
  if (!std::isfinite(m.criteria.loss)) return out;
  out.mean_square = m.criteria.loss;  // over the fitted samples (the residuals' mean square)
  out.tf = m.tf;
  return out;
}

// The profile's trials by step index (0: the centre), each started from
// its neighbour toward the centre.
class Trials {
 public:
  Trials(const Rig& rig, const MeasuredFlow& run, const model::TransferFunction& start, double centre, double step,
         std::size_t bin, const model::IdentifyOptions& identify)
      : rig_(rig), run_(run), start_(start), centre_(centre), step_(step), bin_(bin), identify_(identify) {}

  double Sse(int k) {
    auto it = trials_.find(k);
    if (it != trials_.end()) return it->second.mean_square;
    const model::TransferFunction& from = k == 0 ? start_ : Model(k > 0 ? k - 1 : k + 1);
    return trials_.emplace(k, IdentifiedAt(rig_, run_, centre_ + k * step_, from, bin_, identify_))
        .first->second.mean_square;
  }
  double Least() const {
    double least = INFINITY;
    for (const auto& [k, t] : trials_) least = std::min(least, t.mean_square);
    return least;
  }
  const std::map<int, Trial>& All() const { return trials_; }

 private:
  const model::TransferFunction& Model(int k) {
    Sse(k);
    const Trial& t = trials_.at(k);
    return std::isfinite(t.mean_square) ? t.tf : start_;
  }
  const Rig& rig_;
  const MeasuredFlow& run_;
  const model::TransferFunction& start_;
  double centre_, step_;
  std::size_t bin_;
  model::IdentifyOptions identify_;
  std::map<int, Trial> trials_;
};

// Where the profile crosses `limit` between step indices `in` (below) and
// `out` (above), linear between them.
double Crossing(const std::map<int, Trial>& t, int in, int out, double limit, double scale) {
  const double s0 = scale * t.at(in).mean_square, s1 = scale * t.at(out).mean_square;
  const double f = s1 > s0 ? std::clamp((limit - s0) / (s1 - s0), 0.0, 1.0) : 0.0;
  return in + f * (out - in);
}

// Falling to the least at `kb` and rising after it, each step's reverse
// within `tolerance` (mean squares); a failed trial ends the run checked.
bool Unimodal(const std::map<int, Trial>& all, int kb, double tolerance) {
  double last = all.at(kb).mean_square;
  for (auto it = all.find(kb); it != all.end() && std::isfinite(it->second.mean_square); ++it)
    if (it->second.mean_square < last - tolerance)
      return false;
    else
      last = std::max(last, it->second.mean_square);
  last = all.at(kb).mean_square;
  for (auto it = std::make_reverse_iterator(std::next(all.find(kb)));
       it != all.rend() && std::isfinite(it->second.mean_square); ++it)
    if (it->second.mean_square < last - tolerance)
      return false;
    else
      last = std::max(last, it->second.mean_square);
  return true;
}

}  // namespace

ReidentifiedProfile ProfileReidentified(const Rig& rig, const MeasuredFlow& run, const model::TransferFunction& start,
                                        double centre, double step, double q, std::size_t bin,
                                        const model::IdentifyOptions& identify) {
  ReidentifiedProfile out;
  Trials trials(rig, run, start, centre, step, bin, identify);
  // The SSE over the explain loop's samples: each trial's mean square
  // scaled to the user's flow's count in bins, so that trials whose flow
  // keeps a sample more or less compare alike.
  std::size_t samples = 0;
  for (const FlowSample& s : run.flow->samples) samples += s.valid;
  const double scale = static_cast<double>(samples / std::max<std::size_t>(bin, 1));
  const double delta = kChi2_1_95 * (std::isfinite(q) ? q : 0.0) / scale;  // in mean squares
  for (int k = -2; k <= 2; ++k) trials.Sse(k);
  int lo = -2, hi = 2;
  for (bool grew = true; grew;) {
    grew = false;
    while (lo > -kMaxReidSteps && trials.Sse(lo) <= trials.Least() + delta) trials.Sse(--lo), grew = true;
    while (hi < kMaxReidSteps && trials.Sse(hi) <= trials.Least() + delta) trials.Sse(++hi), grew = true;
  }
  const std::map<int, Trial>& all = trials.All();
  const double least = trials.Least();
  if (!std::isfinite(least)) return out;
  int kb = 0, finite = 0;
  for (const auto& [k, t] : all) {
    out.counts.push_back(centre + k * step), out.sse.push_back(scale * t.mean_square);
    finite += std::isfinite(t.mean_square);
    if (t.mean_square == least) kb = k;
  }
  out.ok = finite >= 3;
  // The best between grid points: the vertex of the parabola through the
  // lowest and its neighbours (within a step of the lowest).
  double best = kb;
  if (all.count(kb - 1) && all.count(kb + 1)) {
    const double a = all.at(kb - 1).mean_square, b = least, c = all.at(kb + 1).mean_square;
    const double curvature = a - 2.0 * b + c;
    if (curvature > 0.0) best = kb + std::clamp(0.5 * (a - c) / curvature, -1.0, 1.0);
  }
  out.best = centre + best * step;
  const double limit = scale * (least + delta);
  int a = kb, b = kb;
  for (const auto& [k, t] : all)
    if (scale * t.mean_square <= limit) a = std::min(a, k), b = std::max(b, k);
  // A trial beyond the band that identified nothing is no crossing: the
  // interval is then not known on that side.
  auto unknown = [&all](int k) { return !all.count(k) || !std::isfinite(all.at(k).mean_square); };
  out.lo_at_edge = unknown(a - 1), out.hi_at_edge = unknown(b + 1);
  out.lo = centre + step * (out.lo_at_edge ? a : Crossing(all, a, a - 1, limit, scale));
  out.hi = centre + step * (out.hi_at_edge ? b : Crossing(all, b, b + 1, limit, scale));
  // A profile that falls and rises again on one side of its least by more
  // than the band's own depth (3.84 q: all the noise allows the SSE to
  // differ between two offsets) was scattered by identify's basins, not
  // shaped by the data: the run does not pin the offset through it. (The
  // sample's 12-s run, under the sanitizer build's rounding: up 14e3 one
  // step past its least and back down 5e3 the next, where its interval
  // ended a tenth of a step out, so several depths; a stepped wheel at 128
  // points, seed 111: back down 0.28 depths, which the noise allows.)
  out.scattered = !Unimodal(all, kb, delta);
  if (out.scattered) out.lo_at_edge = out.hi_at_edge = true;
  return out;
}

}  // namespace bead::explain
