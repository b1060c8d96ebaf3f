// The stripe estimators (libbead/vision/stripe.h) on the twin's stripe
// frames (libbead/sim/stripe_frame.h): 8-bit, 640 x 240, a Gaussian
// stripe of sigma 2 px, peak 200 over 12, waving +-20 rows, speckle 0.2,
// read noise from 0 to 30 dB SNR (peak over noise sd). For each method and
// SNR: found (share of the columns with a centre), wrong (share of those
// more than 3 px off: another peak taken), bias_px and rms_px against the
// true centre over the rest, and speed (bytes_per_second: frame bytes a
// second, one core). Compared in the same run with the plain
// per-column OpenCV way: cv::minMaxLoc down each column, then the parabola
// through the peak and its neighbours.
//   build/bench/bench_stripe --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <functional>
#include <map>

#include "libbead/sim/stripe_frame.h"
#include "libbead/vision/stripe.h"

namespace {

using bead::vision::StripeMethod;

struct Frames {
  std::vector<std::vector<std::uint8_t>> pixels;
  std::vector<std::vector<double>> truth;
  bead::sim::StripeFrameSpec spec;
};

const Frames& FramesAt(int snr_db) {
  static std::map<int, Frames> cache;
  Frames& f = cache[snr_db];
  if (f.pixels.empty()) {
    f.spec.snr_db = snr_db;
    f.spec.speckle = 0.2;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      f.pixels.emplace_back();
      f.truth.emplace_back();
      bead::sim::RenderStripeFrame(f.spec, seed, f.pixels.back(), f.truth.back());
    }
  }
  return f;
}

// Over the lines found: a centre more than 3 px off is a wrong peak
// (noise or speckle taken for the stripe), counted in `wrong`; bias and
// RMS are over the others, so they say how well the stripe is located
// when it is the stripe that was found.
struct Score {
  double sum = 0, sum2 = 0;
  long found = 0, wrong = 0, lines = 0;
  void Add(const std::vector<float>& centres, const std::vector<double>& truth) {
    for (std::size_t u = 0; u < centres.size(); ++u) {
      ++lines;
      if (std::isnan(centres[u])) continue;
      ++found;
      const double e = centres[u] - truth[u];
      if (std::abs(e) > 3.0) {
        ++wrong;
        continue;
      }
      sum += e, sum2 += e * e;
    }
  }
  void Report(benchmark::State& state) const {
    const long good = found - wrong;
    state.counters["bias_px"] = good ? sum / good : NAN;
    state.counters["rms_px"] = good ? std::sqrt(sum2 / good) : NAN;
    state.counters["found"] = lines ? double(found) / lines : 0.0;
    state.counters["wrong"] = found ? double(wrong) / found : 0.0;
  }
};

void Run(benchmark::State& state, const std::function<void(const cv::Mat&, std::vector<float>&)>& find) {
  const Frames& f = FramesAt(static_cast<int>(state.range(0)));
  Score score;
  std::vector<float> centres;
  for (std::size_t k = 0; k < f.pixels.size(); ++k) {
    const cv::Mat frame(f.spec.rows, f.spec.cols, CV_8UC1, const_cast<std::uint8_t*>(f.pixels[k].data()));
    find(frame, centres);
    score.Add(centres, f.truth[k]);
  }
  std::size_t k = 0;
  for (auto _ : state) {
    const cv::Mat frame(f.spec.rows, f.spec.cols, CV_8UC1, const_cast<std::uint8_t*>(f.pixels[k].data()));
    find(frame, centres);
    benchmark::DoNotOptimize(centres.data());
    k = (k + 1) % f.pixels.size();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * f.spec.rows * f.spec.cols);
  score.Report(state);
}

void BM_Stripe(benchmark::State& state, StripeMethod method) {
  bead::vision::StripeOptions o;
  o.axis = bead::vision::StripeAxis::kRows;
  o.method = method;
  bead::vision::StripeCentres s;
  Run(state, [&](const cv::Mat& frame, std::vector<float>& centres) {
    bead::vision::FindStripe(frame, o, s);
    centres.swap(s.centres);
  });
}

// The baseline: the brightest row of each column (cv::minMaxLoc on the
// column's view), the parabola through it and its neighbours.
void BM_OpenCvPerColumn(benchmark::State& state) {
  Run(state, [](const cv::Mat& frame, std::vector<float>& centres) {
    centres.assign(static_cast<std::size_t>(frame.cols), NAN);
    for (int u = 0; u < frame.cols; ++u) {
      double lo = 0, hi = 0;
      cv::Point at;
      cv::minMaxLoc(frame.col(u), &lo, &hi, nullptr, &at);
      const int v = at.y;
      if (hi - lo < 20 || v == 0 || v == frame.rows - 1) continue;
      const double a = frame.at<std::uint8_t>(v - 1, u), c = hi, d = frame.at<std::uint8_t>(v + 1, u);
      const double curvature = a - 2 * c + d;
      centres[static_cast<std::size_t>(u)] = static_cast<float>(v + (curvature < 0 ? 0.5 * (a - d) / curvature : 0.0));
    }
  });
}

void Snr(benchmark::internal::Benchmark* b) {
  for (int snr : {0, 10, 20, 30}) b->Arg(snr);
  b->ArgName("snr_db");
}

BENCHMARK(BM_OpenCvPerColumn)->Apply(Snr);
BENCHMARK_CAPTURE(BM_Stripe, cog, StripeMethod::kCentreOfGravity)->Apply(Snr);
BENCHMARK_CAPTURE(BM_Stripe, gaussian, StripeMethod::kGaussian)->Apply(Snr);
BENCHMARK_CAPTURE(BM_Stripe, parabolic, StripeMethod::kParabolic)->Apply(Snr);
BENCHMARK_CAPTURE(BM_Stripe, steger, StripeMethod::kSteger)->Apply(Snr);

}  // namespace

BENCHMARK_MAIN();
