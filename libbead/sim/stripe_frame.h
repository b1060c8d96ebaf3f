// The twin's camera frames of a laser stripe with a known centre, for the
// stripe estimators' tests and benchmark (libbead/vision/stripe.h).
//
// The stripe runs along the rows: in column u its centre is at row
// c(u) = centre_row + slope u + wave_px sin(2 pi u / wave_period_px). Each
// pixel integrates a Gaussian cross-section of standard deviation sigma_px
// over its height (a sensor pixel collects light over its area):
// peak * (Phi((v + 1/2 - c) / sigma) - Phi((v - 1/2 - c) / sigma)) *
// sqrt(2 pi) sigma, so a pixel on the centre reads about `peak`. Laser
// speckle multiplies the stripe's light by an independent gamma-distributed
// factor of mean 1 and standard deviation `speckle` per pixel (fully
// developed speckle integrated over a pixel: Goodman, "Speckle Phenomena
// in Optics", 2007, sec. 4.6); a reflection adds a second stripe of
// relative height `reflection` at reflection_offset_px below; then
// Gaussian read noise of standard deviation peak / 10^(snr_db / 20); the
// result rounds and clips to 8 bits (saturation at 255).
#pragma once

#include <cstdint>
#include <vector>

namespace bead::sim {

struct StripeFrameSpec {
  int rows = 240, cols = 640;
  double sigma_px = 2.0;
  double peak = 200.0, background = 12.0;  // grey levels
  double snr_db = 30.0;                    // peak over the read noise; infinite: none
  double speckle = 0.0;
  double reflection = 0.0, reflection_offset_px = 40.0;
  double centre_row = 120.3, slope = 0.0, wave_px = 20.0, wave_period_px = 157.0;
};

// pixels: rows x cols, row-major; centres: the true c(u) for each column.
void RenderStripeFrame(const StripeFrameSpec& spec, std::uint64_t seed, std::vector<std::uint8_t>& pixels,
                       std::vector<double>& centres);

}  // namespace bead::sim
