#include "libbead/model/identify.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "libbead/core/error.h"
#include "libbead/model/output_error.h"
#include "libbead/model/projection.h"
#include "libbead/series/interpolate.h"

namespace bead::model {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Lag-one correlation of a residual: its effective sample count is
// N (1 - rho) / (1 + rho).
double EffectiveFraction(const std::vector<double>& e) {
  double c0 = 0, c1 = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    c0 += e[i] * e[i];
    if (i) c1 += e[i] * e[i - 1];
  }
  const double rho = std::clamp(c0 > 0 ? c1 / c0 : 0.0, 0.0, 0.99);
  return (1 - rho) / (1 + rho);
}

ProcessForm ToProcessForm(const TransferFunction& tf) {
  ProcessForm f;
  f.K = tf.DcGain();
  f.Td_s = tf.delay_s;
  f.valid = true;
  for (const auto& r : Roots(tf.den)) {
    if (std::abs(r.imag()) > 1e-9 * std::abs(r) || !(r.real() < 0)) f.valid = false;
    f.Tp_s.push_back(-1.0 / r.real());
  }
  f.Tz_s = std::numeric_limits<double>::quiet_NaN();
  const int m = tf.zeros();
  if (m == 0) f.Tz_s = 0.0;
  if (m == 1 && tf.num.back() != 0.0) f.Tz_s = tf.num[tf.num.size() - 2] / tf.num.back();
  if (m > 1) f.valid = false;
  return f;
}

// The fitted rows: inside the segments, y finite, and past the first
// `skip_s` of each segment (its output there depends on input from before
// the segment, which the record does not hold), except where the process
// started at the segment's first sample (nothing acted before it).
ProjectionProblem MakeProblem(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                              const std::vector<Segment>& segments, int zeros, bool offset, bool initial_state,
                              double skip_s) {
  ProjectionProblem p;
  p.t = &t;
  p.u = &u;
  p.y = &y;
  p.segments = segments.empty() ? WholeRecord(t.size()) : segments;
  p.zeros = zeros;
  p.offset = offset;
  p.initial_state = initial_state;
  for (const Segment& s : p.segments)
    for (std::size_t i = s.begin; i < std::min(s.end, t.size()); ++i)
      if (std::isfinite(y[i]) && (s.process_starts || t[i] >= t[s.begin] + skip_s)) p.rows.push_back(i);
  return p;
}

}  // namespace

namespace {

// Why the data cannot be fitted as given ("" when they can).
std::string CheckInputs(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                        const IdentifyOptions& o) {
  if (o.poles < 1 || o.poles > 7 || o.zeros < 0 || o.zeros > o.poles)
    return "need 1 to 7 poles and 0 <= zeros <= poles";
  if (o.start && (static_cast<int>(o.start->den.size()) != o.poles + 1 ||
                  static_cast<int>(o.start->num.size()) > o.zeros + 1 || !HurwitzStable(o.start->den)))
    return "the warm start is not a stable model of the orders asked (" + std::to_string(o.poles) + " poles, " +
           std::to_string(o.zeros) + " zeros)";
  if (t.size() != u.size() || t.size() != y.size()) return "time, input and output lengths differ";
  for (std::size_t i = 0; i < t.size(); ++i)
    if (!std::isfinite(t[i]) || !std::isfinite(u[i]) || (i && !(t[i] > t[i - 1])))
      return "time must increase and time and input be finite (sample " + std::to_string(i) + ")";
  return "";
}

// Why the fitted samples cannot show the gain ("" when they can): the
// input holds one value over all of them. With the initial state
// estimated, the first max_delay_s of a stretch is left out, and a step
// inside it leaves only its response, which a free initial state mimics
// as well as the input does (a step 10 s into a record, searched to 10 s
// of delay, came back with the gain's sign wrong and a 99 % fit).
std::string InputHeldOverRows(const ProjectionProblem& p, const IdentifyOptions& o) {
  const std::vector<double>& u = *p.u;
  double lo = u[p.rows.front()], hi = lo;
  for (std::size_t i : p.rows) lo = std::min(lo, u[i]), hi = std::max(hi, u[i]);
  if (hi - lo > 1e-12 * std::max(1.0, std::abs(hi))) return "";
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "the input holds one value (%.6g) over every sample fitted (from t = %.4g s%s): nothing there shows "
                "the gain; give a record whose input changes after that, a shorter --max-delay-s, or --from-rest "
                "for a record that starts at rest",
                hi, (*p.t)[p.rows.front()],
                o.estimate_initial_state ? ": each stretch's first max-delay is left out, its output depending on "
                                           "input from before it"
                                         : "");
  return buf;
}

// What every stage shares: the fitted rows, the sample step and the
// slowest pole the data can tell from the initial state's drift (one time
// constant across the longest stretch).
struct Setup {
  ProjectionProblem problem;
  int linear = 0;  // numerator, offset and initial-state parameters
  double dt = 0, slowest = 0;
};

Setup MakeSetup(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                const IdentifyOptions& o, const std::vector<Segment>& segments) {
  Setup st;
  // With a state estimated, the first delay-bound of each stretch is left
  // out; from rest, the input before the record is 0 and nothing is.
  const double skip = o.estimate_initial_state ? (o.delay_s ? *o.delay_s : o.max_delay_s) : 0.0;
  st.problem = MakeProblem(t, u, y, segments, o.zeros, o.estimate_offset, o.estimate_initial_state, skip);
  int estimated_states = 0;
  for (const Segment& s : st.problem.segments)
    estimated_states += o.estimate_initial_state && !s.process_starts ? o.poles : 0;
  st.linear = (o.zeros + 1) + (o.estimate_offset ? 1 : 0) + estimated_states;
  st.dt = MedianStep(t);
  double longest = 0;
  for (const Segment& s : st.problem.segments)
    if (s.end > s.begin) longest = std::max(longest, t[s.end - 1] - t[s.begin]);
  st.slowest = longest > 0 ? 1.0 / longest : 0.0;
  return st;
}

// 1. The delay profile: the linear fit at every step of delay, and the
// search start it gives at each.
void ProfileDelays(const Setup& st, const IdentifyOptions& o, DelayProfile& profile,
                   std::vector<std::vector<double>>& starts) {
  const int n = o.poles;
  if (o.delay_s) {
    profile.delay_s = {*o.delay_s};
  } else {
    const int steps = std::max(1, std::min(o.max_profile_points, static_cast<int>(std::floor(o.max_delay_s / st.dt))));
    for (int k = 0; k <= steps; ++k) profile.delay_s.push_back(o.max_delay_s * k / steps);
  }
  auto run_profile = [&](const SvfSignals& filtered) {
    profile.loss.clear();
    starts.clear();
    for (double d : profile.delay_s) {
      const auto est = SvfDenominator(st.problem, filtered, d);
      profile.loss.push_back(est ? est.value().equation_loss : kInf);
      starts.push_back(est ? ToSearch(est->den, o.real_poles, st.slowest) : std::vector<double>{});
    }
  };
  const double lambda = o.filter_rad_s > 0 ? o.filter_rad_s : 2 * M_PI / (20 * st.dt);
  run_profile(FilterForSvf(st.problem, n, lambda, st.dt));
  // Young's filter works best near the system's own band: a second pass
  // with lambda at twice the fastest pole the first pass found at its best
  // delay (when the user gave no lambda), within [lambda / 10, lambda];
  // kept only where it gives a start at some delay.
  if (o.filter_rad_s > 0) return;
  const auto best_k =
      static_cast<std::size_t>(std::min_element(profile.loss.begin(), profile.loss.end()) - profile.loss.begin());
  if (starts[best_k].empty()) return;
  double fastest = 0;
  for (const auto& r : Roots(FromSearch(starts[best_k].data(), n, o.real_poles)))
    fastest = std::max(fastest, std::abs(r));
  const double lambda2 = std::clamp(2.0 * fastest, lambda / 10, lambda);
  if (!std::isfinite(lambda2) || !(lambda2 < 0.8 * lambda)) return;
  const auto first_loss = profile.loss;
  const auto first_starts = starts;
  run_profile(FilterForSvf(st.problem, n, lambda2, st.dt));
  if (std::none_of(profile.loss.begin(), profile.loss.end(), [](double l) { return std::isfinite(l); })) {
    profile.loss = first_loss;
    starts = first_starts;
  }
}

struct Basin {
  std::size_t at;
  double lo, hi, start_loss;
};

// 2. Basins: local minima of the profile, each spanning to the maxima
// beside it; the best few by the profile, then by the output error of their
// start. Each basin's start: the filter's denominator, or, when one scores
// better by output error, one with every pole at a single frequency from a
// log grid between the slowest pole the stretches resolve and a tenth of
// the sampling rate (the filter's start can sit in a worse optimum, e.g. a
// slow pole standing in for drift).
std::vector<Basin> FindBasins(const Setup& st, const IdentifyOptions& o, const DelayProfile& profile,
                              std::vector<std::vector<double>>& starts) {
  std::vector<Basin> basins;
  const std::size_t K = profile.loss.size();
  const auto& L = profile.loss;
  for (std::size_t k = 0; k < K; ++k) {
    if (!std::isfinite(L[k]) || starts[k].empty()) continue;
    if ((k > 0 && L[k] > L[k - 1]) || (k + 1 < K && L[k] > L[k + 1])) continue;
    if (k > 0 && L[k] == L[k - 1] && !basins.empty() && basins.back().at + 1 == k) continue;  // a flat floor: once
    std::size_t a = k, b = k;
    while (a > 0 && std::isfinite(L[a - 1]) && L[a - 1] >= L[a]) --a;
    while (b + 1 < K && std::isfinite(L[b + 1]) && L[b + 1] >= L[b]) ++b;
    basins.push_back({k, profile.delay_s[a], profile.delay_s[b], kInf});
  }
  std::sort(basins.begin(), basins.end(), [&](const Basin& x, const Basin& y) { return L[x.at] < L[y.at]; });
  basins.resize(std::min<std::size_t>(basins.size(), static_cast<std::size_t>(2 * o.basins)));
  std::vector<std::vector<double>> grid_dens;
  const double lo_p = std::max(2.0 * st.slowest, 1e-3), hi_p = 2 * M_PI / (10 * st.dt);
  for (int k = 0; k < 8 && hi_p > lo_p; ++k) {
    const double p = lo_p * std::pow(hi_p / lo_p, k / 7.0);
    std::vector<std::complex<double>> roots;
    for (int j = 0; j < o.poles; ++j) roots.emplace_back(-p * (1.0 + 0.1 * j), 0.0);
    grid_dens.push_back(FromRoots(roots));
  }
  for (Basin& b : basins) {
    auto score = [&](const std::vector<double>& den) {
      const Projection pr = Project(st.problem, den, profile.delay_s[b.at]);
      return pr.ok ? pr.sse / static_cast<double>(st.problem.rows.size()) : kInf;
    };
    b.start_loss = score(FromSearch(starts[b.at].data(), o.poles, o.real_poles));
    for (const auto& den : grid_dens) {
      const double l = score(den);
      if (l < b.start_loss) b.start_loss = l, starts[b.at] = ToSearch(den, o.real_poles, st.slowest);
    }
  }
  std::sort(basins.begin(), basins.end(), [](const Basin& x, const Basin& y) { return x.start_loss < y.start_loss; });
  return basins;
}

// 3. The joint search over denominator and delay can stop with a poor
// denominator (its steps in the delay cross kinks); the best basin is
// polished: the denominator refitted with the delay held, then the delay
// by golden section over +-1 sample, the denominator refitted at each.
void PolishDelay(const Setup& st, const IdentifyOptions& o, DelayProfile& profile, Refined& best) {
  IdentifyOptions held = o;
  auto at = [&](double d, const std::vector<double>& theta) {
    held.delay_s = d;
    return Refine(st.problem, held, theta, d, d, d, st.dt, st.slowest);
  };
  Refined polished = at(best.delay, best.theta);
  if (polished.loss < best.loss) best = polished;
  const double phi = (std::sqrt(5.0) - 1) / 2;
  double a = std::max(0.0, best.delay - st.dt), b = std::min(o.max_delay_s, best.delay + st.dt);
  double x1 = b - phi * (b - a), x2 = a + phi * (b - a);
  Refined f1 = at(x1, best.theta), f2 = at(x2, best.theta);
  for (int it = 0; it < 6; ++it) {
    if (f1.loss < f2.loss) {
      b = x2, x2 = x1, f2 = f1;
      x1 = b - phi * (b - a);
      f1 = at(x1, f2.theta);
    } else {
      a = x1, x1 = x2, f1 = f2;
      x2 = a + phi * (b - a);
      f2 = at(x2, f1.theta);
    }
  }
  for (const Refined& r : {f1, f2})
    if (r.loss < best.loss) best = r;
  // The basin it came from now ends where the polish did.
  const auto basin =
      std::min_element(profile.basins.begin(), profile.basins.end(),
                       [](const DelayBasin& x, const DelayBasin& y) { return x.refined_loss < y.refined_loss; });
  if (basin != profile.basins.end() && best.loss < basin->refined_loss) {
    basin->delay_s = best.delay;
    basin->refined_loss = best.loss;
  }
}

// The refined basins best first; those whose refinements ended within a
// sample of a better one's are that one, reported once.
void SortDistinct(DelayProfile& profile, double dt) {
  std::sort(profile.basins.begin(), profile.basins.end(),
            [](const DelayBasin& a, const DelayBasin& b) { return a.refined_loss < b.refined_loss; });
  std::vector<DelayBasin> distinct;
  for (const DelayBasin& b : profile.basins)
    if (std::none_of(distinct.begin(), distinct.end(),
                     [&](const DelayBasin& k) { return std::abs(k.delay_s - b.delay_s) < dt; }))
      distinct.push_back(b);
  profile.basins = distinct;
}

// Whether a second basin fits as well: the likelihood ratio of the two with
// the residual's effective sample count, against chi-square(1) at 95 %
// (3.84).
void NoteAmbiguity(DelayProfile& profile, const std::vector<double>& residual, std::size_t rows, double dt) {
  if (profile.basins.size() < 2 || !std::isfinite(profile.basins[1].refined_loss)) return;
  const double n_eff = static_cast<double>(rows) * EffectiveFraction(residual);
  const double l1 = profile.basins[0].refined_loss, l2 = profile.basins[1].refined_loss;
  const double lr = n_eff * std::log(l2 / l1);
  const double grid_step = profile.delay_s.size() > 1 ? profile.delay_s[1] - profile.delay_s[0] : dt;
  if (lr >= 3.84 || std::abs(profile.basins[1].delay_s - profile.basins[0].delay_s) <= 1.5 * grid_step) return;
  profile.ambiguous = true;
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "two delay basins fit alike: %.4g s and %.4g s (loss %.4g vs %.4g); the data do not decide "
                "between them",
                profile.basins[0].delay_s, profile.basins[1].delay_s, l1, l2);
  profile.note = buf;
}

// 1-3 for a cold start: the delay profile, its best basins refined, the
// best polished; nullopt when no delay gave a linear start.
std::optional<Refined> RefineBasins(const Setup& st, const IdentifyOptions& o, DelayProfile& profile) {
  std::vector<std::vector<double>> starts;
  ProfileDelays(st, o, profile, starts);
  const std::vector<Basin> basins = FindBasins(st, o, profile, starts);
  if (basins.empty()) return std::nullopt;
  Refined best;
  for (std::size_t idx = 0; idx < basins.size() && idx < static_cast<std::size_t>(o.basins); ++idx) {
    const Basin& b = basins[idx];
    if (!std::isfinite(b.start_loss)) continue;
    // Bounded by the searched range only: the linear fit's profile is
    // biased by noise, so the output-error optimum may lie past its basin.
    // The joint search only has to reach the basin's optimum's
    // neighbourhood (the best is polished below): at most 15 iterations.
    IdentifyOptions joint = o;
    joint.max_iterations = std::min(o.max_iterations, 15);
    const double hi = o.delay_s ? *o.delay_s : o.max_delay_s;
    const Refined r = Refine(st.problem, joint, starts[b.at], profile.delay_s[b.at], 0.0, hi, st.dt, st.slowest);
    profile.basins.push_back({r.delay, profile.loss[b.at], r.loss});
    if (r.loss < best.loss) best = r;
  }
  if (!o.delay_s && std::isfinite(best.loss)) PolishDelay(st, o, profile, best);
  SortDistinct(profile, st.dt);
  return best;
}

// A warm start (IdentifyOptions::start): one refinement from the start's
// denominator and delay, the delay free within the searched range.
std::optional<Refined> RefineFromStart(const Setup& st, const IdentifyOptions& o) {
  const TransferFunction& s = *o.start;  // its orders checked (CheckInputs)
  const double hi = o.delay_s ? *o.delay_s : o.max_delay_s;
  const double delay = o.delay_s ? *o.delay_s : std::clamp(s.delay_s, 0.0, hi);
  return Refine(st.problem, o, ToSearch(s.den, o.real_poles, st.slowest), delay, 0.0, hi, st.dt, st.slowest);
}

}  // namespace

IdentifiedModel IdentifyTransferFunction(const std::vector<double>& t, const std::vector<double>& u,
                                         const std::vector<double>& y, const IdentifyOptions& o,
                                         const std::vector<Segment>& segments) {
  IdentifiedModel out;
  out.reason = CheckInputs(t, u, y, o);
  if (!out.reason.empty()) return out;
  const Setup st = MakeSetup(t, u, y, o, segments);
  const ProjectionProblem& problem = st.problem;
  if (problem.rows.size() < static_cast<std::size_t>(4 * (o.poles + st.linear + 1))) {
    out.reason = "too few samples (" + std::to_string(problem.rows.size()) + ") for this model";
    return out;
  }
  out.reason = InputHeldOverRows(problem, o);
  if (!out.reason.empty()) return out;
  DelayProfile& profile = out.delay_profile;
  const std::optional<Refined> found = o.start ? RefineFromStart(st, o) : RefineBasins(st, o, profile);
  if (!found) {
    out.reason = "no linear start at any delay (try other orders, or a fixed --delay)";
    return out;
  }
  const Refined& best = *found;
  if (!std::isfinite(best.loss)) {
    out.reason = "output-error refinement found no stable model (try other orders, or a fixed --delay)";
    return out;
  }
  // 4. The model, its operating point and its fit.
  const Projection pr = Project(problem, best.den, best.delay, true, true);
  out.tf = TransferFunction{pr.num, best.den, best.delay};
  out.offset = pr.offset;
  out.initial_state = pr.free_response;
  out.prediction = pr.prediction;
  double umean = 0;
  for (std::size_t i : problem.rows) umean += u[i];
  out.input_level = umean / static_cast<double>(problem.rows.size());
  out.output_level = out.offset + out.tf.DcGain() * out.input_level;
  for (const auto& r : Roots(out.tf.den)) out.poles_real.push_back(r.real()), out.poles_imag.push_back(r.imag());
  if (o.real_poles || (o.poles <= 2 && o.zeros <= 1)) out.process = ToProcessForm(out.tf);
  out.parameters = o.poles + st.linear + (o.delay_s ? 0 : 1);
  std::vector<double> yr, pr_rows;
  for (std::size_t i : problem.rows) yr.push_back(y[i]), pr_rows.push_back(out.prediction[i]);
  out.fit_percent = FitPercent(yr, pr_rows);
  out.fitted_samples = problem.rows.size();
  out.criteria = CriteriaFromResiduals(pr.residual, out.parameters);
  NoteAmbiguity(profile, pr.residual, problem.rows.size(), st.dt);
  if (!o.delay_s && best.delay >= o.max_delay_s - st.dt) {
    profile.at_limit = true;
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "the delay, %.4g s, is at the end of the searched range (max delay %.4g s): the best delay may "
                  "lie beyond it; search further (--max-delay-s)",
                  best.delay, o.max_delay_s);
    profile.limit_note = buf;
  }
  out.ok = true;
  return out;
}

}  // namespace bead::model
