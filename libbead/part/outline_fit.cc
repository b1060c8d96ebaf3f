#include "libbead/part/outline_fit.h"

#include <algorithm>

#include "libbead/part/part_kernel.h"
#include "libbead/part/superellipse_sums.h"

namespace bead::part {
namespace {

// The residuals' sum of squares at e, and the normal equations J^T J and
// J^T r of the fitted parameters. The derivatives are
// the ellipse's top's, where it is what the sensor sees: with u = (x - x0) / a
// and s = sqrt(1 - u^2), d/dx0 = b u / (a s), d/dz0 = 1, d/da = b u^2 / (a s)
// (plus the aspect times s where b = aspect a is held), d/db = s; zero
// where the surface below is seen (a kink: the side it is on). s is held
// at 0.02 or more: at the ellipse's end its slope is unbounded, and a
// point there says where the end is only to within a point spacing.
struct Normal {
  double rss = 0.0;
  Eigen::Matrix4d JtJ = Eigen::Matrix4d::Zero();
  Eigen::Vector4d Jtr = Eigen::Vector4d::Zero();
};

Normal Residuals(const Window& w, const Ellipse& e, const FitShape& shape) {
  Normal n;
  // Only the points under the ellipse depend on it; the others' residuals
  // are summed once (Window::bare). Those under it: four a register
  // (part/part_kernel.h).
  const auto lo = static_cast<std::size_t>(std::lower_bound(w.x.begin(), w.x.end(), e.x0 - e.a) - w.x.begin());
  const auto hi = static_cast<std::size_t>(std::upper_bound(w.x.begin(), w.x.end(), e.x0 + e.a) - w.x.begin());
  const EllipseSums sums = e.p == 2.0
                               ? ActivePartKernel().ellipse(w.x.data(), w.z.data(), w.old.data(), lo, std::max(lo, hi),
                                                            {e.x0, e.z0, e.a, e.b, shape.aspect})
                               : SuperellipseSums(w, lo, std::max(lo, hi), e, shape.aspect);
  n.rss = w.bare[lo] + (w.bare.back() - w.bare[std::max(lo, hi)]) + sums.rss;
  for (int i = 0, k = 0; i < 4; ++i) {
    for (int j = i; j < 4; ++j, ++k) n.JtJ(i, j) = n.JtJ(j, i) = sums.jtj[k];
    n.Jtr[i] = sums.jtr[i];
  }
  return n;
}

// The damped Gauss-Newton step of the first K parameters (K: 3 with the
// aspect held, else 4): fixed-size matrices, solved in registers.
template <int K>
Eigen::Vector4d DampedStep(const Normal& at, double lambda) {
  Eigen::Matrix<double, K, K> A = at.JtJ.topLeftCorner<K, K>();
  A.diagonal() += lambda * (A.diagonal().array() + 1e-12).matrix();
  Eigen::Vector4d step = Eigen::Vector4d::Zero();
  step.head<K>() = A.ldlt().solve(-at.Jtr.head<K>());
  return step;
}

}  // namespace

// Levenberg-Marquardt from `e` (as part/least_squares.h: the damping
// raised tenfold on a step that does not lower the residual, to 0.3 of
// itself on one that does; done below 1e-7 of the residual, or when the
// step to try moves no parameter by kSettledMm (not tried: the kinks
// otherwise make the steps creep, and a higher damping only shortens
// them; stopping there, not after the tries that fail, takes the fit's
// residuals from 29.2 to 27.3 a profile on the bench's wall); J^T J of
// the fitted parameters at the end in JtJ (its top left). kSettledMm: a
// tenth of a profiler's noise; a step under it moves the groove by less
// than its width (at most the bead's, 6 mm on the twin) times 1e-3 mm, a
// tenth of its sigma's smallest part (the walls' sampling, ~0.07 mm^2).
// (1e-4 fitted twice as many residuals for the same figures.)
constexpr double kSettledMm = 1e-3;

double FitOutline(const Window& w, Ellipse& e, const FitShape& shape, Eigen::Matrix4d& JtJ) {
  const std::size_t k = shape.Params();
  shape.Keep(e);
  Normal at = Residuals(w, e, shape);
  double lambda = 1e-3;
  for (int it = 0; it < 80; ++it) {
    bool better = false, converged = false;
    for (int tries = 0; tries < 8 && !better; ++tries) {
      const Eigen::Vector4d step = k == 3 ? DampedStep<3>(at, lambda) : DampedStep<4>(at, lambda);
      if (step.cwiseAbs().maxCoeff() < kSettledMm) {
        converged = true;
        break;
      }
      Ellipse trial = e;
      for (std::size_t i = 0; i < k; ++i) trial[i] += step[static_cast<Eigen::Index>(i)];
      shape.Keep(trial);
      const Normal there = Residuals(w, trial, shape);
      if (std::isfinite(there.rss) && there.rss < at.rss) {
        converged = at.rss - there.rss < 1e-7 * at.rss;
        e = trial, at = there;
        lambda = std::max(lambda * 0.3, 1e-9), better = true;
      } else {
        lambda *= 10.0;
      }
    }
    if (!better || converged) break;
  }
  JtJ = at.JtJ;
  return at.rss;
}

}  // namespace bead::part
