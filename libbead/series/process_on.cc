#include "libbead/series/process_on.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "libbead/series/interpolate.h"

namespace bead {
namespace {

double Percentile95Abs(const std::vector<double>& v) {
  std::vector<double> a;
  for (double x : v)
    if (std::isfinite(x)) a.push_back(std::abs(x));
  if (a.empty()) return 0.0;
  const std::size_t k = static_cast<std::size_t>(0.95 * static_cast<double>(a.size() - 1));
  std::nth_element(a.begin(), a.begin() + static_cast<long>(k), a.end());
  return a[k];
}

// The stretch's first output closer to zero than `fraction` of its median.
bool RisesFromZero(const std::vector<double>& y, std::size_t begin, std::size_t end, double fraction) {
  std::vector<double> a;
  for (std::size_t i = begin; i < end; ++i)
    if (std::isfinite(y[i])) a.push_back(std::abs(y[i]));
  if (a.empty() || !std::isfinite(y[begin])) return false;
  std::nth_element(a.begin(), a.begin() + static_cast<long>(a.size() / 2), a.end());
  return std::abs(y[begin]) < fraction * a[a.size() / 2];
}

// Each sample: 1 where the process is off (the output at zero while the
// input is not, for at least min_off_samples in a row), when the output
// has its floor at zero at all.
std::vector<char> MarkOff(const std::vector<double>& u, const std::vector<double>& y, const ProcessOnOptions& o) {
  const std::size_t n = y.size();
  std::vector<char> off(n, 0);
  const double y_scale = Percentile95Abs(y), u_scale = Percentile95Abs(u);
  double y_min = INFINITY;
  for (double v : y)
    if (std::isfinite(v)) y_min = std::min(y_min, v);
  if (!(y_scale > 0 && y_min >= -o.zero_fraction * y_scale)) return off;
  auto at_zero = [&](std::size_t k) {
    return std::isfinite(y[k]) && std::abs(y[k]) <= o.zero_fraction * y_scale &&
           std::abs(u[k]) > o.zero_fraction * u_scale;
  };
  std::size_t i = 0;
  while (i < n) {
    if (!at_zero(i)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < n && at_zero(j)) ++j;
    if (j - i >= static_cast<std::size_t>(o.min_off_samples))
      std::fill(off.begin() + static_cast<long>(i), off.begin() + static_cast<long>(j), 1);
    i = j;
  }
  return off;
}

}  // namespace

ProcessOn FindProcessOn(const std::vector<double>& t, const std::vector<double>& u, const std::vector<double>& y,
                        const ProcessOnOptions& o) {
  ProcessOn out;
  const std::size_t n = t.size();
  if (n == 0) return out;
  const double step = n > 1 ? MedianStep(t) : 1.0;
  const std::vector<char> off = MarkOff(u, y, o);
  auto exclude = [&](double a, double b, const char* why) {
    if (!out.excluded.empty() && out.excluded.back().reason == why &&
        a - out.excluded.back().t_end_s <= o.gap_steps * step)
      out.excluded.back().t_end_s = b;
    else
      out.excluded.push_back({a, b, why});
  };
  std::size_t begin = n;  // start of the open segment
  bool begin_after_off = false;
  std::size_t last_ok = n;
  auto close = [&](std::size_t end) {
    if (begin >= n) return;
    if (end - begin >= static_cast<std::size_t>(o.min_segment_samples)) {
      if (begin_after_off && RisesFromZero(y, begin, end, o.start_fraction)) {
        // At rest at the last sample the output read zero: the stretch takes
        // that sample (its model output is the rest it shows) from the
        // process-off one before it.
        if (begin >= 2 && off[begin - 2]) {
          for (Exclusion& e : out.excluded)
            if (e.t_end_s == t[begin - 1] && e.reason == "process off") e.t_end_s = t[begin - 2];
          --begin;
        }
        out.segments.push_back({begin, end, true});
      } else {
        out.segments.push_back({begin, end, false});
      }
      out.fitted_samples += end - begin;
    } else {
      exclude(t[begin], t[end - 1], "too short to fit");
    }
    begin = n;
  };
  std::size_t off_start = n;
  for (std::size_t i = 0; i < n; ++i) {
    const bool usable = std::isfinite(y[i]) && !off[i];
    if (off[i]) {
      if (off_start == n) off_start = i;
    } else if (off_start != n) {
      exclude(t[off_start], t[i - 1], "process off");
      off_start = n;
    }
    if (!usable) continue;
    if (last_ok < n && t[i] - t[last_ok] > o.gap_steps * step) {
      close(last_ok + 1);
      if (std::none_of(off.begin() + static_cast<long>(last_ok), off.begin() + static_cast<long>(i),
                       [](char c) { return c != 0; }))
        exclude(t[last_ok], t[i], "no samples");
    } else if (last_ok < n && i > last_ok + 1 &&
               std::any_of(off.begin() + static_cast<long>(last_ok + 1), off.begin() + static_cast<long>(i),
                           [](char c) { return c != 0; })) {
      close(last_ok + 1);
    }
    if (begin == n) {
      begin = i;
      begin_after_off = i > 0 && off[i - 1];
    }
    last_ok = i;
  }
  if (off_start != n) exclude(t[off_start], t[n - 1], "process off");
  if (last_ok < n) close(last_ok + 1);
  std::sort(out.excluded.begin(), out.excluded.end(),
            [](const Exclusion& a, const Exclusion& b) { return a.t_begin_s < b.t_begin_s; });
  return out;
}

std::string DescribeExclusions(const std::vector<Exclusion>& excluded) {
  std::string s;
  for (const Exclusion& e : excluded) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s%s %.2f-%.2f s", s.empty() ? "" : "; ", e.reason.c_str(), e.t_begin_s, e.t_end_s);
    s += buf;
  }
  return s;
}

}  // namespace bead
