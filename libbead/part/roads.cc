#include "libbead/part/roads.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "libbead/core/median.h"
#include "libbead/part/road_arcs.h"

namespace bead::part {
namespace {

// A region of the gain: points [first, last] above the edge floor, the
// bare point either side (where it exists), and whether the field of view
// (or a dropout) ends it on a side.
struct Region {
  std::size_t first = 0, last = 0;
  bool cut_left = false, cut_right = false;
};

std::vector<Region> RegionsOf(std::span<const double> x, std::span<const double> d, double floor, double tau,
                              double max_gap) {
  std::vector<Region> out;
  for (std::size_t i = 0; i < d.size();) {
    if (!(d[i] > floor)) {
      ++i;
      continue;
    }
    Region r{i, i};
    double top = d[i];
    while (r.last + 1 < d.size() && d[r.last + 1] > floor && x[r.last + 1] - x[r.last] <= max_gap)
      top = std::max(top, d[++r.last]);
    r.cut_left = r.first == 0 || x[r.first] - x[r.first - 1] > max_gap;
    r.cut_right = r.last + 1 == d.size() || x[r.last + 1] - x[r.last] > max_gap;
    if (top > tau && r.last - r.first >= 2) out.push_back(r);
    i = r.last + 1;
  }
  return out;
}

// The gain smoothed over +-half points.
std::vector<double> Smoothed(std::span<const double> d, std::size_t half) {
  std::vector<double> s(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    const std::size_t a = i >= half ? i - half : 0, b = std::min(d.size() - 1, i + half);
    double sum = 0.0;
    for (std::size_t k = a; k <= b; ++k) sum += d[k];
    s[i] = sum / static_cast<double>(b - a + 1);
  }
  return s;
}

// The crests of the smoothed gain s that stand out of the valleys either
// side (their prominence) by `noise` (threshold_sigmas noise sigmas) and by
// `fraction` of their height. (Not by the detection threshold's floor in
// mm: a surface below that lies off by a constant lifts crest and valley
// alike, and roads a quarter the twin's size, whose valleys at 0.7 w are
// 0.08-0.11 mm deep before smoothing, were found as one to three in
// 78-83 % of profiles.)
std::vector<std::size_t> Crests(const std::vector<double>& s, double noise, double fraction) {
  std::vector<std::size_t> out;
  for (std::size_t i = 1; i + 1 < s.size(); ++i) {
    if (!(s[i] > s[i - 1] && s[i] >= s[i + 1])) continue;
    std::size_t l = i, r = i, lmin = i, rmin = i;
    while (l > 0 && s[l - 1] <= s[i]) --l, lmin = s[l] < s[lmin] ? l : lmin;
    while (r + 1 < s.size() && s[r + 1] <= s[i]) ++r, rmin = s[r] < s[rmin] ? r : rmin;
    const double prominence = s[i] - std::max(s[lmin], s[rmin]);
    if (prominence >= noise && prominence >= fraction * s[i]) out.push_back(i);
  }
  return out;
}

// A road's start at each crest: half an ellipse standing on the surface
// below, as wide as the lowest points between it and its neighbouring
// crests (the region's ends beyond the outer ones) leave it; the aspect the
// crests' median.
std::vector<Arc> StartArcs(std::span<const double> x, const std::vector<double>& s,
                           const std::vector<std::size_t>& crests) {
  std::vector<Arc> out;
  auto lowest = [&s](std::size_t a, std::size_t b) {
    return static_cast<std::size_t>(
        std::min_element(s.begin() + static_cast<std::ptrdiff_t>(a), s.begin() + static_cast<std::ptrdiff_t>(b) + 1) -
        s.begin());
  };
  for (std::size_t c = 0; c < crests.size(); ++c) {
    const std::size_t l = lowest(c == 0 ? 0 : crests[c - 1], crests[c]);
    const std::size_t r = lowest(crests[c], c + 1 == crests.size() ? s.size() - 1 : crests[c + 1]);
    Arc a;
    a.x0 = x[crests[c]];
    a.h = s[crests[c]];
    a.a = std::max(0.5 * (x[r] - x[l]), 1e-3);
    a.k = a.h / a.a;
    out.push_back(a);
  }
  std::vector<double> k;
  for (const Arc& a : out) k.push_back(a.k);
  if (!k.empty()) {
    const double middle = MiddleInPlace(k);
    for (Arc& a : out) a.k = middle;
  }
  return out;
}

// Whether the fit with its exponent freed is the better account of the
// same roads: its residual lower by more than one parameter's worth of
// noise at 0.1 % (chi-squared, 1 degree of freedom: 10.8) and every road
// where the ellipses put it (within a quarter of its half-width): a freed
// exponent that merges two roads into one box is not the same roads.
bool KeepsTheRoads(const ArcFit& ellipses, const ArcFit& freed, std::size_t points) {
  if (!freed.ok || freed.arcs.size() != ellipses.arcs.size()) return false;
  const double dof = static_cast<double>(points) - 3.0 * static_cast<double>(ellipses.arcs.size()) - 2.0;
  if (dof <= 0 || (ellipses.rss - freed.rss) * dof / freed.rss < 10.8) return false;
  for (std::size_t i = 0; i < freed.arcs.size(); ++i)
    if (std::abs(freed.arcs[i].x0 - ellipses.arcs[i].x0) > 0.25 * ellipses.arcs[i].a) return false;
  return true;
}

double MedianNear(std::span<const double> x, std::span<const double> d, double at) {
  const std::size_t k = static_cast<std::size_t>(std::lower_bound(x.begin(), x.end(), at) - x.begin());
  const std::size_t a = k > 1 ? k - 1 : 0, b = std::min(x.size() - 1, a + 2);
  std::vector<double> v(d.begin() + static_cast<std::ptrdiff_t>(a), d.begin() + static_cast<std::ptrdiff_t>(b) + 1);
  return MiddleInPlace(v);
}

// Each arc's share of the measured gain at x (laid in the arcs' order): the
// slab between the surfaces before and after it, the measured gain in
// place of the top; gain no arc covers goes to the nearest arc.
void Own(std::span<const Arc> arcs, double x, double gain, std::vector<double>& share) {
  const double g = std::max(gain, 0.0);
  std::fill(share.begin(), share.end(), 0.0);
  double below = 0.0;
  std::size_t top = arcs.size();
  for (std::size_t i = 0; i < arcs.size(); ++i) {
    const double after = std::max(below, arcs[i].At(x));
    if (after > below) top = i;
    share[i] = std::max(0.0, std::min(g, after) - std::min(g, below));
    below = after;
  }
  if (top == arcs.size()) {
    std::size_t near = 0;
    for (std::size_t i = 1; i < arcs.size(); ++i)
      if (std::abs(arcs[i].x0 - x) < std::abs(arcs[near].x0 - x)) near = i;
    share[near] = g;
    return;
  }
  double lower = 0.0;
  for (std::size_t i = 0; i < top; ++i) lower += share[i];
  std::fill(share.begin() + static_cast<std::ptrdiff_t>(top), share.end(), 0.0);
  share[top] = g - lower;
}

// Each arc's material over the points (laid in the arcs' order).
std::vector<double> Areas(std::span<const Arc> arcs, std::span<const double> xs, std::span<const double> ds) {
  std::vector<double> share(arcs.size()), area(arcs.size(), 0.0), before(arcs.size(), 0.0);
  for (std::size_t j = 0; j < xs.size(); ++j) {
    Own(arcs, xs[j], ds[j], share);
    for (std::size_t i = 0; i < share.size(); ++i) {
      if (j > 0) area[i] += 0.5 * (before[i] + share[i]) * (xs[j] - xs[j - 1]);
      before[i] = share[i];
    }
  }
  return area;
}

// The region's roads, left to right (laid in that order).
std::vector<Road> RegionRoads(std::span<const double> x, std::span<const double> d, const Region& g, double tau,
                              double noise_tau, double min_a, const RoadOptions& o) {
  const std::size_t lo = g.cut_left ? g.first : g.first - 1, hi = g.cut_right ? g.last : g.last + 1;
  const auto xs = x.subspan(lo, hi - lo + 1), ds = d.subspan(lo, hi - lo + 1);
  const double spacing = (xs.back() - xs.front()) / static_cast<double>(std::max<std::size_t>(xs.size() - 1, 1));
  // Smoothed over +-0.15 mm, or three points where that is narrower (a
  // fine sensor's: 0.15 mm is a tenth of a road 1.5 mm wide).
  const std::size_t half =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(std::min(0.15, 3.0 * spacing) / spacing)));
  const std::vector<double> smooth = Smoothed(ds, half);
  std::vector<std::size_t> crests = Crests(smooth, noise_tau, o.min_valley_fraction);
  // A region with no crest that stands out (a ramp, a road whose top runs
  // off the field): one road at its highest point.
  if (crests.empty())
    crests.push_back(static_cast<std::size_t>(std::max_element(smooth.begin(), smooth.end()) - smooth.begin()));
  std::vector<Arc> start = StartArcs(xs, smooth, crests);
  if (start.size() > static_cast<std::size_t>(o.max_roads)) start.resize(static_cast<std::size_t>(o.max_roads));
  // Ellipses first, then their exponent freed from where they settled (a
  // free exponent from the crests' rough start can settle a hidden road
  // millimetres off).
  const ArcFit ellipses = FitArcs(xs, ds, start, min_a, tau, false);
  ArcFit fit = ellipses;
  if (ellipses.ok) {
    const ArcFit freed = FitArcs(xs, ds, ellipses.arcs, min_a, tau, true);
    if (KeepsTheRoads(ellipses, freed, xs.size())) fit = freed;
  }
  std::sort(fit.arcs.begin(), fit.arcs.end(), [](const Arc& a, const Arc& b) { return a.x0 < b.x0; });
  std::vector<Road> roads(fit.arcs.size());
  if (!fit.ok || roads.empty()) {
    roads.assign(1, Road{});  // a region the model could not explain: one row that says so
    return roads;
  }
  const std::vector<double> area = Areas(fit.arcs, xs, ds);
  // The model's top is the highest arc whatever the order: the same fit
  // split as if laid right to left (the arcs taken from the right).
  std::vector<Arc> reversed(fit.arcs.rbegin(), fit.arcs.rend());
  std::vector<double> other = Areas(reversed, xs, ds);
  std::reverse(other.begin(), other.end());
  const double rms = std::sqrt(fit.rss / static_cast<double>(xs.size()));
  for (std::size_t i = 0; i < roads.size(); ++i) {
    const Arc& a = fit.arcs[i];
    Road& r = roads[i];
    r.status = RoadStatus::kValid;
    r.center_x_mm = a.x0, r.area_mm2 = area[i], r.width_mm = a.Chord(), r.fit_rms_mm = rms;
    r.area_other_order_mm2 = other[i];
    // Its top as measured where it is the surface the sensor sees.
    const bool seen = a.At(a.x0) >= LayeredAt(fit.arcs, a.x0) - 1e-9;
    r.height_mm = seen ? MedianNear(xs, ds, a.x0) : a.h;
  }
  if (g.cut_left) roads.front().status = RoadStatus::kCutByEdge;
  if (g.cut_right) roads.back().status = RoadStatus::kCutByEdge;
  return roads;
}

// The points with a finite gain, spikes left out.
void Despiked(std::span<const float> xf, std::span<const double> gain, double spike_mm, std::vector<double>& x,
              std::vector<double>& d) {
  std::vector<double> xa, da;
  for (std::size_t j = 0; j < xf.size() && j < gain.size(); ++j)
    if (std::isfinite(xf[j]) && std::isfinite(gain[j])) xa.push_back(xf[j]), da.push_back(gain[j]);
  for (std::size_t j = 0; j < da.size(); ++j) {
    const std::size_t a = j >= 2 ? j - 2 : 0, b = std::min(da.size() - 1, j + 2);
    std::vector<double> near(da.begin() + static_cast<std::ptrdiff_t>(a),
                             da.begin() + static_cast<std::ptrdiff_t>(b) + 1);
    if (std::abs(da[j] - MiddleInPlace(near)) <= spike_mm) x.push_back(xa[j]), d.push_back(da[j]);
  }
}

std::vector<Road> LeftFirst(std::span<const float> xf, std::span<const double> gain, double noise_mm,
                            const RoadOptions& o) {
  std::vector<double> x, d;
  Despiked(xf, gain, o.spike_mm, x, d);
  std::vector<Road> out;
  if (x.size() < 10) return out;
  const double tau = o.Threshold(noise_mm);
  const double floor = std::max(o.min_edge_floor_mm, o.edge_floor_sigmas * noise_mm);
  const double spacing = (x.back() - x.front()) / static_cast<double>(x.size() - 1);
  for (const Region& g : RegionsOf(x, d, floor, tau, o.max_gap_mm)) {
    const std::vector<Road> roads = RegionRoads(x, d, g, tau, o.threshold_sigmas * noise_mm, 2.0 * spacing, o);
    out.insert(out.end(), roads.begin(), roads.end());
  }
  return out;
}

}  // namespace

const char* RoadStatusName(RoadStatus s) {
  switch (s) {
    case RoadStatus::kValid:
      return "ok";
    case RoadStatus::kCutByEdge:
      return "cut_by_edge";
    case RoadStatus::kNoFit:
      return "no_fit";
  }
  return "unknown";
}

std::vector<Road> FindRoads(std::span<const float> x, std::span<const double> gain, double noise_mm,
                            const RoadOptions& o) {
  std::vector<Road> roads;
  if (o.laid_left_first) {
    roads = LeftFirst(x, gain, noise_mm, o);
  } else {  // laid right to left: the same, mirrored
    std::vector<float> mx(x.rbegin(), x.rend());
    std::vector<double> md(gain.rbegin(), gain.rend());
    for (float& v : mx) v = -v;
    roads = LeftFirst(mx, md, noise_mm, o);
    std::reverse(roads.begin(), roads.end());
    for (Road& r : roads) r.center_x_mm = -r.center_x_mm;
  }
  // Each road's distance from its neighbour laid before it, over that
  // road's width.
  for (std::size_t i = 1; i < roads.size(); ++i) {
    const Road& earlier = roads[o.laid_left_first ? i - 1 : i];
    roads[o.laid_left_first ? i : i - 1].spacing_over_width =
        (roads[i].center_x_mm - roads[i - 1].center_x_mm) / earlier.width_mm;
  }
  return roads;
}

void RoadsSummary::Add(const std::vector<Road>& found, bool laid_left_first) {
  ++profiles_by_count[found.size()];
  roads += found.size();
  for (std::size_t i = 0; i < found.size(); ++i) {
    cut_by_edge += found[i].status == RoadStatus::kCutByEdge;
    no_fit += found[i].status == RoadStatus::kNoFit;
    if (i > 0 && found[i].valid() && found[i - 1].valid()) {
      const double spacing = found[laid_left_first ? i : i - 1].spacing_over_width;
      if (std::isfinite(spacing)) spacing_over_width.Add(spacing);
    }
    const bool paired = (i > 0 && found[i - 1].valid()) || (i + 1 < found.size() && found[i + 1].valid());
    if (found[i].valid() && paired && found[i].area_mm2 > 0.0)
      order_change.Add(std::abs(found[i].area_other_order_mm2 / found[i].area_mm2 - 1.0));
  }
}

namespace {

// Under this relative change in the other order, 95 % of the roads' areas
// are taken not to rest on it (a road's area is known to about 0.1 % from
// the noise over its points: tests/part_generator/test_roads_pipe.py).
constexpr double kOrderMatters = 0.005;

}  // namespace

double RoadsSummary::MedianSpacing() const { return spacing_over_width.Quantile(0.5); }

std::string RoadsSummary::OrderInWords(bool left_first) const {
  if (order_change.empty()) return "";
  const double median = order_change.Quantile(0.5), high = order_change.Quantile(0.95);
  const char* other = left_first ? "right to left" : "left to right";
  char line[400];
  if (high < kOrderMatters)
    std::snprintf(line, sizeof line,
                  "the roads' areas do not rest on the order they were laid in (laid %s, 95 %% of them would move "
                  "by under %.1f %%)",
                  other, 100.0 * kOrderMatters);
  else
    std::snprintf(line, sizeof line,
                  "the profiles cannot show the order the roads were laid in (the model's top, the highest cap, is "
                  "the same either way); laid %s, each road's area would be %.1f %% apart (median; %.1f %% at the "
                  "95th percentile): --laid gives the order",
                  other, 100.0 * median, 100.0 * high);
  return line;
}

std::string RoadsSummary::SpacingInWords() const {
  const double r = MedianSpacing();
  if (!std::isfinite(r)) return "";
  char line[400];
  const char* verdict =
      r < kFlatTopCriticalRatio   ? "below both critical spacings: the valleys between roads should fill"
      : r < kTangentCriticalRatio ? "between the two critical spacings: the models disagree on whether the valleys fill"
                                  : "above both critical spacings: valleys stay between the roads";
  std::snprintf(line, sizeof line,
                "centre spacing %.3f of the width (median of %zu pairs); the flat-top overlap model's critical "
                "spacing is 0.667 w (Suryakumar et al. 2011), the tangent overlapping model's 0.738 w (Ding et al. "
                "2015): %s",
                r, spacing_over_width.seen(), verdict);
  return line;
}

}  // namespace bead::part
