// bead measure's words for a layer's pooled bead shape (part/layer_grooves.h:
// PooledShape), from part_scan.cc.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "tools/part_scan.h"

namespace bead::tools {
namespace {

// "v +- sigma" to the sigma's second significant digit, at least three
// decimals (a sigma under half a thousandth printed as +- 0.000 read as
// none at all).
std::string WithSigma(double v, double sigma) {
  const int decimals =
      std::isfinite(sigma) && sigma > 0.0 ? std::clamp(1 - static_cast<int>(std::floor(std::log10(sigma))), 3, 6) : 3;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f +- %.*f", decimals, v, decimals, sigma);
  return buf;
}

// A tamped bead's shape as it is held, in mm.
void SayTampedHold(const part::PooledShape& s) {
  std::printf(
      "    held as a tamped bead's: half-height %s mm and ends' arcs %s mm wide in every profile (its aspect and "
      "corner share from its own width: more flow widens a tamped bead, not heightens it)\n",
      WithSigma(s.half_height_mm, s.half_height_sigma_mm).c_str(), WithSigma(s.corner_mm, s.corner_sigma_mm).c_str());
}

}  // namespace

// The layer's pooled bead shape, and in words how far from an ellipse (or
// that an ellipse is assumed).
void SayShape(const part::PooledShape& s) {
  if (s.Tamped() && s.exponent_layer >= 0) {
    // Held at each profile's own width: the aspect this layer's own fits
    // pooled (at the carried exponent) is not what is held, and not said.
    std::printf(
        "    bead shape: layer %lld's tamped bead, carried from an earlier layer (too few of this layer's beads "
        "were placed at their walls to solve its own)\n",
        static_cast<long long>(s.exponent_layer));
    SayTampedHold(s);
    return;
  }
  std::printf("    bead shape (%s%zu %s pooled): half-height over half-width %s", s.AspectAtWalls() ? "" : "its first ",
              s.rows, s.AspectAtWalls() ? "of its first profiles, those placed at their walls," : "profiles",
              WithSigma(s.aspect, s.aspect_sigma).c_str());
  if (!s.exponent_solved) {
    // One test for "the tops and walls do not pin the shape", the misfit
    // line's (SayMisfits): most of the rows estimated showed walls unsolved.
    char why[400];
    if (s.ShapeUnpinned())
      std::snprintf(why, sizeof why,
                    "%zu of its first %zu profiles show walls at both ends, but the shape each one's top solves does "
                    "not stand over them by more than the noise and the ends' cells, a point spacing wide, leave in "
                    "doubt: their tops and walls do not pin their own shape",
                    s.walls_unsolved, s.estimated);
    else
      std::snprintf(why, sizeof why, "few of its beads overhang to show their walls%s",
                    s.walls_unsolved > 0 ? ", and of those that do, the tops of some do not pin their shape" : "");
    std::printf(
        "; an ellipse assumed (too few of its beads were placed at their walls to solve the exponent: %s): the sigma "
        "is the fitted beads' spread alone, not what a shape other than the ellipse would leave\n",
        why);
  } else if (part::IsStadium(s.exponent)) {
    // A stadium's p is its corner share c, negated (part/superellipse.h).
    std::printf(
        ", a stadium: flat on top, each end a quarter ellipse over %s of the half-width (%s; 1 is the ellipse, the "
        "aspect half circles; the two errors correlated %+.2f)%s\n",
        WithSigma(-s.exponent, s.exponent_sigma).c_str(),
        s.NotAnEllipse() ? "its top flatter than an ellipse's" : "an ellipse, within two sigmas", s.correlation,
        s.exponent_layer >= 0 ? ", carried from an earlier layer" : "");
    if (s.Tamped()) SayTampedHold(s);
    if (s.stadium_by_evidence)
      std::printf(
          "    (most of its first beads' tops alone did not pin a shape standing over their walls; over the "
          "layer's rows the stadium's family followed the tops better than the superellipse's, beyond their "
          "noise, and each was placed with it)\n");
  } else {
    // The words follow the model: a shape not an ellipse is fitted as itself.
    const char* words = !s.NotAnEllipse()  ? "an ellipse, within two sigmas"
                        : s.exponent > 2.0 ? "toward a box: flatter on top, steeper at the sides"
                                           : "toward a diamond: narrower at top and bottom";
    if (s.exponent_layer >= 0)
      std::printf(
          ", exponent %s carried from layer %lld (%s; too few of this layer's beads overhang to show their walls and "
          "solve it: one material, one process; its profiles fitted with it)\n",
          WithSigma(s.exponent, s.exponent_sigma).c_str(), static_cast<long long>(s.exponent_layer), words);
    else
      std::printf(", exponent %s (%s; the two errors correlated %+.2f)\n",
                  WithSigma(s.exponent, s.exponent_sigma).c_str(), words, s.correlation);
  }
  if (s.footprint)
    std::printf(
        "    the profiler's points average over a footprint (most beads' walls hold a point between the surface below "
        "and the top): each such end's cell stays its wall's, its place in the cell counted whole in the sigma; where "
        "within the spot's reach the bead's end lies, its points cannot tell (the spot's shape is not known), the "
        "same in every profile: the shape's sigmas hold it (+-%.3f of the aspect)\n",
        s.aspect_footprint_sigma);
}

}  // namespace bead::tools
