#include "libbead/vision/stripe.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "libbead/core/error.h"
#include "libbead/vision/stripe_line.h"
#include "libbead/vision/stripe_steger.h"

namespace bead::vision {
namespace {

using detail::LinePeak;
using detail::LineScan;
using detail::Verdict;

double Saturation(int depth) {
  switch (depth) {
    case CV_8U:
      return 255.0;
    case CV_16U:
      return 65535.0;
    default:
      return std::numeric_limits<double>::infinity();
  }
}

void CheckOptions(const StripeOptions& o) {
  auto bad = [](const std::string& what) { throw Error("stripe options: " + what); };
  if (!(o.min_peak > 0.0) || !std::isfinite(o.min_peak)) bad("min_peak must be a positive number of grey levels");
  if (!(o.threshold >= 0.0) || !std::isfinite(o.threshold)) bad("threshold must be 0 (none) or a grey level");
  if (!(o.min_width_px >= 0.0)) bad("min_width_px must be 0 or more");
  if (!(o.max_width_px > o.min_width_px) || !(o.max_width_px <= 1000.0))
    bad("max_width_px must exceed min_width_px and be at most 1000 px");
  if (!(o.min_relative >= 0.0) || !(o.min_relative < 1.0))
    bad("min_relative must be 0 (no test) or a fraction under 1 of the frame's stripe height");
  if (!(o.steger_sigma_px >= 0.0) || !(o.steger_sigma_px <= 100.0))
    bad("steger_sigma_px must be 0 (from the peak's width) or at most 100 px");
}

// The chosen peak of one line, by the rule; `previous` is the last
// found centre of an earlier line (NaN when none) for the nearest rule.
const LinePeak& Choose(const std::vector<LinePeak>& peaks, PeakRule rule, double previous) {
  auto centre = [](const LinePeak& p) { return 0.5 * (p.left + p.right); };
  switch (rule) {
    case PeakRule::kFirst:
      return peaks.front();
    case PeakRule::kLast:
      return peaks.back();
    case PeakRule::kWidest:
      return *std::max_element(peaks.begin(), peaks.end(),
                               [](const LinePeak& a, const LinePeak& b) { return a.Width() < b.Width(); });
    case PeakRule::kNearest:
      if (std::isfinite(previous))
        return *std::min_element(peaks.begin(), peaks.end(), [&](const LinePeak& a, const LinePeak& b) {
          return std::abs(centre(a) - previous) < std::abs(centre(b) - previous);
        });
      [[fallthrough]];
    case PeakRule::kStrongest:
      break;
  }
  return *std::max_element(peaks.begin(), peaks.end(),
                           [](const LinePeak& a, const LinePeak& b) { return a.Height() < b.Height(); });
}

template <typename T>
void Search(const cv::Mat& lines, const StripeOptions& o, StripeCentres& out) {
  const double saturated = Saturation(lines.depth());
  out.centres.assign(static_cast<std::size_t>(lines.rows), std::numeric_limits<float>::quiet_NaN());
  StripeStats& s = out.stats;
  s = StripeStats{};
  s.lines = lines.rows;
  LineScan scan;
  std::vector<float> height(static_cast<std::size_t>(lines.rows), 0.0f), tallest;
  std::vector<unsigned char> several(static_cast<std::size_t>(lines.rows), 0), clipped(several);
  double previous = std::numeric_limits<double>::quiet_NaN();
  for (int y = 0; y < lines.rows; ++y) {
    const T* f = lines.ptr<T>(y);
    detail::ScanLine(f, lines.cols, o, saturated, scan);
    if (scan.tallest > 0.0) tallest.push_back(static_cast<float>(scan.tallest));
    if (scan.peaks.empty()) {
      switch (scan.rejected) {
        case Verdict::kTooWide:
          ++s.too_wide;
          break;
        case Verdict::kTooNarrow:
          ++s.too_narrow;
          break;
        case Verdict::kFlatTop:
          ++s.flat_top;
          break;
        case Verdict::kAtBorder:
          ++s.at_border;
          break;
        default:
          ++s.no_peak;
          break;
      }
      continue;
    }
    const LinePeak& p = Choose(scan.peaks, o.rule, previous);
    double c = 0.0;
    if (o.method == StripeMethod::kSteger) {
      const double sigma = o.steger_sigma_px > 0.0 ? o.steger_sigma_px : std::max(1.0, p.Width() / 3.0);
      if (!detail::StegerCentre(lines, (p.first + p.last) / 2, y, sigma, c)) {
        ++s.unresolved;
        continue;
      }
    } else {
      c = detail::SubPixelCentre(f, p, o.method, o.threshold);
    }
    const auto k = static_cast<std::size_t>(y);
    out.centres[k] = static_cast<float>(c);
    height[k] = static_cast<float>(p.Height());
    several[k] = scan.peaks.size() > 1;
    clipped[k] = p.value >= saturated;
    previous = c;
  }
  // The frame's stripe height: the 95th percentile over the lines of
  // their tallest peak of any shape (where the stripe runs nearly along
  // the lines it is too wide there, but as tall).
  float cut = 0.0f;
  if (!tallest.empty() && o.min_relative > 0.0) {
    auto at = tallest.begin() + static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(tallest.size() - 1));
    std::nth_element(tallest.begin(), at, tallest.end());
    cut = static_cast<float>(o.min_relative * *at);
  }
  for (std::size_t k = 0; k < height.size(); ++k) {
    if (std::isnan(out.centres[k])) continue;
    if (height[k] < cut) {
      out.centres[k] = std::numeric_limits<float>::quiet_NaN();
      ++s.faint;
      continue;
    }
    ++s.found;
    s.several += several[k];
    s.saturated += clipped[k];
  }
}

void SearchLines(const cv::Mat& lines, const StripeOptions& o, StripeCentres& out) {
  switch (lines.depth()) {
    case CV_8U:
      Search<std::uint8_t>(lines, o, out);
      break;
    case CV_16U:
      Search<std::uint16_t>(lines, o, out);
      break;
    default:
      Search<float>(lines, o, out);
      break;
  }
}

}  // namespace

void FindStripe(const cv::Mat& frame, const StripeOptions& options, StripeCentres& out) {
  if (frame.empty()) throw Error("camera frame: empty");
  if (frame.type() != CV_8UC1 && frame.type() != CV_16UC1 && frame.type() != CV_32FC1)
    throw Error("camera frame: type " + cv::typeToString(frame.type()) +
                ", expected one channel of 8-bit, 16-bit or 32-bit float grey levels");
  CheckOptions(options);
  // The searched lines are the rows of `lines`: the frame itself when the
  // stripe runs down it (one centre per row), its transpose when the
  // stripe runs across (one centre per column).
  cv::Mat transposed;
  auto across = [&]() -> const cv::Mat& {
    if (transposed.empty()) cv::transpose(frame, transposed);
    return transposed;
  };
  if (options.axis == StripeAxis::kRows || options.axis == StripeAxis::kColumns) {
    out.axis = options.axis;
    SearchLines(options.axis == StripeAxis::kRows ? across() : frame, options, out);
    return;
  }
  StripeCentres down;
  SearchLines(frame, options, down);
  down.axis = StripeAxis::kColumns;
  SearchLines(across(), options, out);
  out.axis = StripeAxis::kRows;
  if (down.stats.found > out.stats.found) std::swap(out, down);
}

std::string Name(StripeAxis axis) {
  switch (axis) {
    case StripeAxis::kRows:
      return "rows";
    case StripeAxis::kColumns:
      return "columns";
    default:
      return "auto";
  }
}

std::string Name(StripeMethod method) {
  switch (method) {
    case StripeMethod::kCentreOfGravity:
      return "cog";
    case StripeMethod::kParabolic:
      return "parabolic";
    case StripeMethod::kSteger:
      return "steger";
    default:
      return "gaussian";
  }
}

std::string Name(PeakRule rule) {
  switch (rule) {
    case PeakRule::kWidest:
      return "widest";
    case PeakRule::kFirst:
      return "first";
    case PeakRule::kLast:
      return "last";
    case PeakRule::kNearest:
      return "nearest";
    default:
      return "strongest";
  }
}

namespace {
template <typename E>
E Parse(const std::string& name, std::initializer_list<E> all, const char* what) {
  std::string names;
  for (E e : all) {
    if (Name(e) == name) return e;
    names += (names.empty() ? "" : ", ") + Name(e);
  }
  throw Error(std::string("stripe ") + what + " '" + name + "': expected one of " + names);
}
}  // namespace

StripeAxis ParseStripeAxis(const std::string& name) {
  return Parse(name, {StripeAxis::kAuto, StripeAxis::kRows, StripeAxis::kColumns}, "axis");
}
StripeMethod ParseStripeMethod(const std::string& name) {
  return Parse(
      name, {StripeMethod::kCentreOfGravity, StripeMethod::kGaussian, StripeMethod::kParabolic, StripeMethod::kSteger},
      "method");
}
PeakRule ParsePeakRule(const std::string& name) {
  return Parse(name, {PeakRule::kStrongest, PeakRule::kWidest, PeakRule::kFirst, PeakRule::kLast, PeakRule::kNearest},
               "rule");
}

StripeStats& StripeStats::operator+=(const StripeStats& o) {
  lines += o.lines, found += o.found, no_peak += o.no_peak, too_wide += o.too_wide, too_narrow += o.too_narrow;
  at_border += o.at_border, unresolved += o.unresolved, several += o.several, saturated += o.saturated;
  flat_top += o.flat_top, faint += o.faint;
  return *this;
}

std::string Describe(const StripeStats& s) {
  std::ostringstream o;
  o << s.lines << " lines: " << s.found << " found";
  if (s.saturated || s.several) {
    o << " (";
    if (s.saturated) o << s.saturated << " saturated" << (s.several ? ", " : "");
    if (s.several) o << s.several << " with several peaks";
    o << ")";
  }
  const std::pair<int, const char*> rest[] = {{s.no_peak, "no peak"},
                                              {s.too_wide, "too wide"},
                                              {s.too_narrow, "too narrow"},
                                              {s.flat_top, "flat-topped (a lit region)"},
                                              {s.at_border, "at the frame's border"},
                                              {s.unresolved, "no line-like curvature"},
                                              {s.faint, "faint (under the frame's stripe)"}};
  for (const auto& [n, what] : rest)
    if (n) o << ", " << n << " " << what;
  return o.str();
}

}  // namespace bead::vision
