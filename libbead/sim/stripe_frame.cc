#include "libbead/sim/stripe_frame.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace bead::sim {
namespace {

// The light of a unit-peak Gaussian stripe centred at c that falls on the
// pixel spanning rows [v - 1/2, v + 1/2].
double PixelLight(int v, double c, double sigma) {
  const double k = 1.0 / (std::sqrt(2.0) * sigma);
  return 0.5 * (std::erf((v + 0.5 - c) * k) - std::erf((v - 0.5 - c) * k)) * std::sqrt(2.0 * M_PI) * sigma;
}

}  // namespace

void RenderStripeFrame(const StripeFrameSpec& s, std::uint64_t seed, std::vector<std::uint8_t>& pixels,
                       std::vector<double>& centres) {
  std::mt19937_64 rng(seed);
  const double noise = std::isfinite(s.snr_db) ? s.peak / std::pow(10.0, s.snr_db / 20.0) : 0.0;
  std::normal_distribution<double> read(0.0, noise > 0.0 ? noise : 1.0);
  // Gamma of shape 1 / speckle^2 and scale speckle^2: mean 1, sd speckle.
  const bool speckled = s.speckle > 0.0;
  std::gamma_distribution<double> speckle(speckled ? 1.0 / (s.speckle * s.speckle) : 1.0,
                                          speckled ? s.speckle * s.speckle : 1.0);
  centres.resize(static_cast<std::size_t>(s.cols));
  for (int u = 0; u < s.cols; ++u)
    centres[static_cast<std::size_t>(u)] =
        s.centre_row + s.slope * u + s.wave_px * std::sin(2.0 * M_PI * u / s.wave_period_px);
  pixels.resize(static_cast<std::size_t>(s.rows) * static_cast<std::size_t>(s.cols));
  const double reach = 8.0 * s.sigma_px + 1.0;
  for (int v = 0; v < s.rows; ++v)
    for (int u = 0; u < s.cols; ++u) {
      const double c = centres[static_cast<std::size_t>(u)];
      double light = 0.0;
      if (std::abs(v - c) < reach) light += PixelLight(v, c, s.sigma_px);
      const double r = c + s.reflection_offset_px;
      if (s.reflection > 0.0 && std::abs(v - r) < reach) light += s.reflection * PixelLight(v, r, s.sigma_px);
      if (speckled && light > 0.0) light *= speckle(rng);
      const double level = s.background + s.peak * light + (noise > 0.0 ? read(rng) : 0.0);
      pixels[static_cast<std::size_t>(v) * static_cast<std::size_t>(s.cols) + static_cast<std::size_t>(u)] =
          static_cast<std::uint8_t>(std::clamp(std::round(level), 0.0, 255.0));
    }
}

}  // namespace bead::sim
