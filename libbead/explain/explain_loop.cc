#include "libbead/explain/explain_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <optional>

#include "libbead/core/error.h"
#include "libbead/explain/effect_fit.h"
#include "libbead/explain/confounding.h"
#include "libbead/explain/parameter_covariance.h"
#include "libbead/model/fit_metrics.h"

namespace bead::explain {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using Set = EffectSet;

double Bic(double sse, std::size_t n, std::size_t p) {
  const double nn = static_cast<double>(n);
  return nn * std::log(std::max(sse, 1e-300) / nn) + static_cast<double>(p) * std::log(nn);
}

// Time blocks: every sample's block index, `blocks` of equal duration.
std::vector<std::vector<std::size_t>> Blocks(const std::vector<double>& t, int blocks) {
  std::vector<std::vector<std::size_t>> out(static_cast<std::size_t>(blocks));
  const double t0 = t.front(), span = t.back() - t.front();
  for (std::size_t i = 0; i < t.size(); ++i) {
    auto b = static_cast<std::size_t>(span > 0 ? (t[i] - t0) / span * blocks : 0);
    out[std::min(b, out.size() - 1)].push_back(i);
  }
  return out;
}

// The held-out test: on the held-out samples, the drop in squared error
// per added parameter against the error left per effective sample,
//   F = ((SSE_before - SSE_after) / p) / (SSE_after / N_eff),
// N_eff = N (1 - rho) / (1 + rho) for the lag-one correlation rho of the
// residual left; F p is chi-square with p degrees of freedom when the
// effect is not real (its parameters were fitted on other data, so a false
// effect makes the held-out error larger, not smaller).
double HeldOutF(const SeriesData& v, const Set& before, const Set& after, const std::vector<std::size_t>& rows,
                std::size_t added_parameters) {
  // Each side's initial states (local to the start of a stretch, which a
  // held-out block may hold alone) re-solved on the held-out samples.
  Set b = before, a = after;
  SolveLinearOf(v, b, rows, "initial");
  SolveLinearOf(v, a, rows, "initial");
  const std::vector<double> rb = Residual(v, b), ra = Residual(v, a);
  const double sse_b = Sse(rb, rows), sse_a = Sse(ra, rows);
  std::vector<double> left;
  for (std::size_t i : rows) left.push_back(ra[i]);
  const double rho = std::clamp(LagOneCorrelation(left), 0.0, 0.99);
  const double n_eff = static_cast<double>(rows.size()) * (1 - rho) / (1 + rho);
  if (!(sse_a > 0) || added_parameters == 0) return 0.0;
  return (sse_b - sse_a) / static_cast<double>(added_parameters) / (sse_a / n_eff);
}

// A periodic term against the residual's own colour: the held-out F of
// the same term on the same part turning at other rates (its angle scaled
// about the start), at least two frequency resolutions away from the
// part's own rate and its second harmonic. A colored residual gives such
// surrogates large F too; a real periodic effect beats all of them.
double LargestSurrogateF(const SeriesData& d, const SeriesData& v, bool separate_validation, const Set& current,
                         const Effect& effect, const std::vector<std::size_t>& estimation,
                         const std::vector<std::size_t>& held_out) {
  const auto& angle = d.parts[static_cast<std::size_t>(effect.part)].angle_rad;
  const double revs = std::abs(angle.back() - angle.front()) / (2 * std::numbers::pi);
  double largest = -kInf;
  for (int k = 2; k <= 6; ++k) {
    for (int sign : {-1, 1}) {
      const double factor = 1.0 + sign * k / revs;
      if (factor < 0.3 || std::abs(factor - 2.0) < 2.0 / revs) continue;
      auto scaled = [&](const SeriesData& src) {
        SeriesData copy = src;
        RotatingPart part = copy.parts[static_cast<std::size_t>(effect.part)];
        const double a0 = part.angle_rad.front();
        for (double& a : part.angle_rad) a = a0 + factor * (a - a0);
        part.name += " (surrogate)";
        copy.parts.push_back(part);
        return copy;
      };
      const SeriesData ds = scaled(d);
      const SeriesData vs = separate_validation ? scaled(v) : ds;
      Effect e = effect;
      e.part = static_cast<int>(ds.parts.size()) - 1;
      Set trial = current;
      trial.push_back(Activate(e));
      Fit(ds, trial, estimation, current.size());
      largest = std::max(largest, HeldOutF(vs, current, trial, held_out, trial.back().params.size()));
    }
  }
  return largest;
}

double Rms(const std::vector<double>& r) {
  double s = 0;
  std::size_t n = 0;
  for (double x : r)
    if (std::isfinite(x)) s += x * x, ++n;
  return n ? std::sqrt(s / static_cast<double>(n)) : 0.0;
}

double FitOf(const SeriesData& d, const Set& set) {
  std::vector<double> y, pred;
  Evaluate(d, set, y, pred);
  return model::FitPercent(y, pred);
}

Diagnosis Diagnose(const SeriesData& d, const Set& set, const ExplainOptions& o) {
  Diagnosis g;
  g.residual = Residual(d, set);
  g.fit_pct = FitOf(d, set);
  g.rms = Rms(g.residual);
  g.whiteness = ResidualWhiteness(g.residual, o.lags);
  g.input = ResidualInputCorrelation(g.residual, d.u, o.lags);
  g.spectrum = ResidualSpectrum(d.t, g.residual, o.spectrum_max_hz);
  return g;
}

std::vector<FittedParameter> Parameters(const Active& a, const std::vector<double>& sd) {
  std::vector<FittedParameter> out;
  const std::size_t nl = a.nl();
  for (std::size_t k = 0; k < a.params.size(); ++k) {
    const std::string& name = k < nl ? a.effect.nonlinear[k] : a.effect.linear[k - nl];
    out.push_back({name, a.params[k], 1.96 * sd[k]});
  }
  if (a.effect.part >= 0 && a.params.size() == 2) {
    // Amplitude and phase of c cos + s sin, with first-order uncertainties.
    const double c = a.params[0], s = a.params[1], amp = std::hypot(c, s);
    const double sd_amp = std::hypot(sd[0], sd[1]) / std::sqrt(2.0);
    out.push_back({"amplitude_rel", amp, 1.96 * sd_amp});
    out.push_back({"phase_rad", std::atan2(s, c), amp > 0 ? 1.96 * sd_amp / amp : kInf});
  }
  return out;
}

AddedEffect Describe(const Active& a, const std::vector<double>& sd) {
  AddedEffect e;
  e.name = a.effect.name;
  e.description = a.effect.description;
  e.tracks = a.effect.tracks;
  e.parameters = Parameters(a, sd);
  return e;
}

// The held-out test of `candidate` against `null`, both fitted on the
// estimation rows: BIC drop there and held-out F.
struct Test {
  double bic_drop = 0, f = 0;
  Set fitted;
};
// `joint`: every nonlinear parameter refitted with the candidate's (the
// base model's delay too); else only the candidate's own (a screening).
Test TryEffect(const SeriesData& d, const SeriesData& v, const Set& null, const Effect& candidate,
               const std::vector<std::size_t>& estimation, const std::vector<std::size_t>& held_out, bool joint) {
  Test t;
  t.fitted = null;
  t.fitted.push_back(Activate(candidate));
  Fit(d, t.fitted, estimation, joint ? 0 : null.size());
  const double bic_null = Bic(Sse(Residual(d, null), estimation), estimation.size(), ParameterCount(null));
  t.bic_drop = bic_null - Bic(Sse(Residual(d, t.fitted), estimation), estimation.size(), ParameterCount(t.fitted));
  t.f = HeldOutF(v, null, t.fitted, held_out, t.fitted.back().params.size());
  return t;
}

// The rows the loop estimates on and those it tests on: every other of the
// time blocks, or (with another run held out) all of this one and all of
// that one.
struct Rows {
  std::vector<std::size_t> all, estimation, held_out;
  const SeriesData* validation = nullptr;
};
Rows SplitRows(const SeriesData& d, const ExplainOptions& o) {
  Rows r;
  r.all.resize(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) r.all[i] = i;
  const auto blocks = Blocks(d.t, std::max(o.blocks, 4));
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    auto& to = b % 2 == 0 ? r.estimation : r.held_out;
    to.insert(to.end(), blocks[b].begin(), blocks[b].end());
  }
  r.validation = o.validation ? o.validation : &d;
  if (o.validation) {
    r.estimation = r.all;
    r.held_out.resize(o.validation->size());
    for (std::size_t i = 0; i < r.held_out.size(); ++i) r.held_out[i] = i;
  }
  return r;
}

// The model as given, each stretch's initial state fitted (as identify's
// fit and compare take it: a stretch's free response is no part of a
// model, and one from rest is not the model's error; a part's stretches
// are its layers, seconds long, where a slow mode's free response is the
// whole record).
Set AsGiven(const SeriesData& d, const CatalogueOptions& catalogue, const std::vector<std::size_t>& all) {
  Set set;
  for (const Effect& e : BaseRefit(d, catalogue))
    if (e.feature == "initial") set.push_back(Activate(e));
  if (!set.empty()) Fit(d, set, all);
  return set;
}

// The base model at its best: gain, operating point and delay refitted,
// each started from the fit of the ones before it.
Set FittedBase(const SeriesData& d, const CatalogueOptions& catalogue, const std::vector<std::size_t>& all) {
  Set est;
  for (const Effect& e : BaseRefit(d, catalogue)) est.push_back(Activate(e));
  for (std::size_t k = 0; k < est.size(); ++k) {
    Set partial(est.begin(), est.begin() + static_cast<long>(k + 1));
    Fit(d, partial, all);
    for (std::size_t j = 0; j <= k; ++j) est[j].params = partial[j].params;
  }
  return est;
}

// The guard: the base with a linear correction of its dynamics, fitted; on
// the first round what it says of the base model goes in the report.
Set Guard(const SeriesData& d, const Rows& rows, const Set& base, const Effect& dynamics, bool first,
          const ExplainOptions& o, ExplainReport& report) {
  const Test g = TryEffect(d, *rows.validation, base, dynamics, rows.estimation, rows.held_out, true);
  if (first) {
    const std::size_t p = dynamics.linear.size();
    report.base.tested = true;
    report.base.heldout_f = g.f;
    report.base.threshold = ChiSquareQuantile(1.0 - o.alpha, static_cast<int>(p)) / static_cast<double>(p);
    report.base.misspecified = g.f > report.base.threshold && g.bic_drop > 0;
    const double n = static_cast<double>(rows.held_out.size());
    report.base.rms_before = std::sqrt(Sse(Residual(*rows.validation, base), rows.held_out) / n);
    report.base.rms_after = std::sqrt(Sse(Residual(*rows.validation, g.fitted), rows.held_out) / n);
  }
  return g.fitted;
}

// One round: every candidate not yet added tried against the base and its
// effects so far; the one that passes every test with the largest BIC drop.
struct Round {
  int best = -1;
  double bic_drop = 0.0, f = 0.0;
  Set fitted;                  // the best's, on the estimation rows
  std::vector<Active> passed;  // every candidate that passed, as fitted
};
Round TryCandidates(const SeriesData& d, const Rows& rows, const Set& current, const std::vector<Effect>& catalogue,
                    const std::vector<bool>& used, const Set* guard_null, int round, const ExplainOptions& o,
                    ExplainReport& report) {
  Round r;
  const SeriesData& v = *rows.validation;
  // Every candidate of the round is a test: Bonferroni keeps the chance
  // of adding a false one in a round at alpha.
  const auto left = static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
  const double level = 1.0 - o.alpha / static_cast<double>(std::max<std::size_t>(left, 1));
  for (std::size_t c = 0; c < catalogue.size(); ++c) {
    if (used[c]) continue;
    // Screened with the base model's delay held; what passes is fitted
    // jointly with it and tested again.
    Test t = TryEffect(d, v, current, catalogue[c], rows.estimation, rows.held_out, false);
    const std::size_t p_new = t.fitted.back().params.size();
    const double critical = ChiSquareQuantile(level, static_cast<int>(p_new)) / static_cast<double>(p_new);
    bool ok = t.bic_drop > 0 && t.f > critical;
    if (ok) {
      t = TryEffect(d, v, current, catalogue[c], rows.estimation, rows.held_out, true);
      ok = t.bic_drop > 0 && t.f > critical;
    }
    double surrogate = NAN, guarded = NAN;
    if (ok && guard_null) {
      guarded = TryEffect(d, v, *guard_null, catalogue[c], rows.estimation, rows.held_out, true).f;
      ok = guarded > critical;
    }
    if (ok && catalogue[c].part >= 0) {
      surrogate =
          LargestSurrogateF(d, v, o.validation != nullptr, current, catalogue[c], rows.estimation, rows.held_out);
      ok = t.f > surrogate;
    }
    report.candidates.push_back({round, catalogue[c].name, t.bic_drop, t.f, surrogate, guarded, false});
    if (ok) r.passed.push_back(t.fitted.back());
    if (ok && t.bic_drop > r.bic_drop)
      r.best = static_cast<int>(c), r.bic_drop = t.bic_drop, r.f = t.f, r.fitted = t.fitted;
  }
  return r;
}

// What adding the round's best did, on the whole record.
AddedEffect Added(const SeriesData& d, const Set& before, const Set& after, const Round& r) {
  AddedEffect added;
  added.name = after.back().effect.name;
  added.description = after.back().effect.description;
  added.tracks = after.back().effect.tracks;
  added.fit_before_pct = FitOf(d, before);
  added.fit_after_pct = FitOf(d, after);
  added.rms_before = Rms(Residual(d, before));
  added.rms_after = Rms(Residual(d, after));
  added.bic_drop = r.bic_drop;
  added.heldout_f = r.f;
  return added;
}

// Every parameter from the final joint fit, with its interval; what trades
// with what; the alternatives that also passed.
void FinalFit(const SeriesData& d, Set& current, std::size_t base_terms,
              const std::vector<std::pair<Active, Active>>& alternatives, const std::vector<std::size_t>& all,
              ExplainReport& report) {
  Refine(d, current, all);
  const ParameterCovariance cov = Covariance(d, current, all);
  for (std::size_t e = 0; e < current.size(); ++e) {
    if (e < base_terms)
      report.base_refit.push_back(Describe(current[e], cov.sd[e]));
    else
      report.effects_added[e - base_terms].parameters = Describe(current[e], cov.sd[e]).parameters;
  }
  report.final_covariance = cov.Matrix();
  report.confounded = Confounded(current, cov, base_terms);
  for (const auto& [kept, alt] : alternatives) SayAlternative(d, kept, alt, report);
  for (const Active& a : current) {
    report.final_effects.push_back(a.effect);
    report.final_params.push_back(a.params);
  }
  report.base_terms = base_terms;
}

// What is left: every significant peak, matched to a rotating part.
void SayUnexplained(const SeriesData& d, ExplainReport& report) {
  const double span = d.t.back() - d.t.front();
  for (const SpectrumPeak& peak : report.after.spectrum.peaks) {
    Unexplained u{"periodic", "", peak.frequency_hz, peak.power, peak.false_alarm};
    for (const RotatingPart& part : d.parts) {
      const double rate = std::abs(part.angle_rad.back() - part.angle_rad.front()) / (2 * std::numbers::pi * span);
      for (int k = 1; k <= 3 && u.tracks.empty(); ++k)
        if (std::abs(peak.frequency_hz - k * rate) <= std::max(1.5 / span, 0.03 * peak.frequency_hz))
          u.tracks = part.name + " x" + std::to_string(k);
    }
    if (u.tracks.empty()) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "frequency %.3f Hz (no rotating part)", peak.frequency_hz);
      u.tracks = buf;
    }
    report.unexplained.push_back(u);
  }
  if (!report.after.whiteness.white && report.unexplained.empty())
    report.unexplained.push_back(
        {"correlated residual", "no single frequency (not white: chi-square above its 99 % limit)", 0, 0, 1});
}

}  // namespace

ExplainReport Explain(const SeriesData& d, const ExplainOptions& o) {
  if (d.size() < 20 || (o.validation && o.validation->size() < 20))
    throw Error("explain: fewer than 20 samples (" + std::to_string(d.size()) + ") to explain");
  ExplainReport report;
  const Rows rows = SplitRows(d, o);
  const std::vector<Effect> catalogue = Catalogue(d, o.catalogue);
  report.before = Diagnose(d, AsGiven(d, o.catalogue, rows.all), o);
  Set current = FittedBase(d, o.catalogue, rows.all);
  const std::size_t base_terms = current.size();
  const Effect dynamics = DynamicsCorrection(d);
  std::vector<bool> used(catalogue.size(), false);
  std::vector<std::pair<Active, Active>> alternatives;  // (kept, another that passed in its round)
  for (int round = 0; round < o.max_effects; ++round) {
    Set current_est = current;
    Refine(d, current_est, rows.estimation);
    std::optional<Set> guard_null;
    if (!dynamics.name.empty()) guard_null = Guard(d, rows, current_est, dynamics, round == 0, o, report);
    const Round r =
        TryCandidates(d, rows, current_est, catalogue, used, guard_null ? &*guard_null : nullptr, round, o, report);
    if (r.best < 0) break;
    const auto best = static_cast<std::size_t>(r.best);
    for (const Active& alt : r.passed)
      if (alt.effect.name != r.fitted.back().effect.name) alternatives.push_back({r.fitted.back(), alt});
    for (auto& cand : report.candidates)
      if (cand.round == round && cand.name == catalogue[best].name) cand.accepted = true;
    used[best] = true;
    // Refit on the whole record, from the estimation-half values.
    Set after = r.fitted;
    Refine(d, after, rows.all);
    report.effects_added.push_back(Added(d, current, after, r));
    current = after;
  }
  FinalFit(d, current, base_terms, alternatives, rows.all, report);
  // The wheel-position shift that best aligns the data, profiled.
  for (const Effect& e : catalogue)
    if (e.kind == Effect::Kind::kPositionShift && d.shifted) EstimateShift(d, current, e, rows.all, report);
  report.after = Diagnose(d, current, o);
  SayUnexplained(d, report);
  return report;
}

}  // namespace bead::explain
