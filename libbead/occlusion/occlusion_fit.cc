#include "libbead/occlusion/occlusion_fit.h"

#include <ceres/ceres.h>

#include "libbead/fit/solver_options.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "libbead/occlusion/occlusion_pool.h"
#include "libbead/occlusion/shape_models.h"

namespace bead::occlusion {
namespace {

struct Points {
  std::vector<double> u, h;  // u: along the reference line (x frame), h: height
};

// Seen points between the edges (and a margin), along the line.
Points SeenPoints(const ProfileView& view, const BeadGeometry& g, double margin) {
  Points p;
  const ReferenceLine& line = g.reference;
  const double norm = std::sqrt(1 + line.slope * line.slope);
  const double lo = g.left_edge_x_mm * norm - margin, hi = g.right_edge_x_mm * norm + margin;
  for (std::size_t i = 0; i < view.x_mm.size(); ++i) {
    const double x = view.x_mm[i], z = view.z_mm[i];
    if (!std::isfinite(x) || !std::isfinite(z)) continue;
    const double s = (x + line.slope * (z - line.intercept_mm)) / norm;
    if (s < lo || s > hi) continue;
    p.u.push_back(s);
    p.h.push_back(line.HeightAt(x, z));
  }
  return p;
}

template <typename Family>
struct EnvelopeResidual {
  EnvelopeResidual(double u, double h) : u(u), h(h) {}
  template <typename T>
  bool operator()(const T* center, const T* params, T* residual) const {
    residual[0] = T(h) - Family::Envelope(params, T(u) - center[0]);
    return true;
  }
  double u, h;
};

// Fits `Family` (parameters in p, centre in center); returns RSS, or -1 on failure.
template <typename Family>
double Fit(const Points& pts, double huber, double& center, std::vector<double>& p, const std::vector<double>& lo,
           const std::vector<double>& hi, ceres::Problem& problem) {
  for (std::size_t i = 0; i < pts.u.size(); ++i)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<EnvelopeResidual<Family>, 1, 1, Family::kParams>(
                                 new EnvelopeResidual<Family>(pts.u[i], pts.h[i])),
                             new ceres::HuberLoss(huber), &center, p.data());
  for (int k = 0; k < Family::kParams; ++k) {
    problem.SetParameterLowerBound(p.data(), k, lo[static_cast<std::size_t>(k)]);
    problem.SetParameterUpperBound(p.data(), k, hi[static_cast<std::size_t>(k)]);
  }
  const ceres::Solver::Options so = fit::QuietDenseOptions(200);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable()) return -1;
  double rss = 0;
  for (std::size_t i = 0; i < pts.u.size(); ++i) {
    const double r = pts.h[i] - Family::Envelope(p.data(), pts.u[i] - center);
    rss += r * r;
  }
  return rss;
}

// Covariance of the parameter block, scaled by the residual variance.
bool ParamCovariance(ceres::Problem& problem, double* params, int k, double scale, Eigen::MatrixXd& cov) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.null_space_rank = -1;
  ceres::Covariance covariance(co);
  std::vector<std::pair<const double*, const double*>> blocks = {{params, params}};
  if (!covariance.Compute(blocks, &problem)) return false;
  cov.resize(k, k);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(k, k);
  covariance.GetCovarianceBlock(params, params, m.data());
  cov = m * scale;
  return true;
}

double Bic(double rss, int n, int k) {
  return n * std::log(std::max(rss, 1e-30) / n) + k * std::log(static_cast<double>(n));
}

// The fan's shadow of the widest points at height c and half-width a
// about the centre s0 (s frame ~ x frame), with the laser's origin known.
struct Shadow {
  const BeadGeometry& g;
  const OcclusionOptions& o;
  double norm;
  double operator()(double c, double s0, double a) const {
    if (!o.laser_origin || c <= 0) return 0.0;
    const double z_origin =
        o.laser_origin->z_mm - (g.reference.intercept_mm + g.reference.slope * o.laser_origin->x_mm);
    return FanShadowArea(c, (s0 - a) / norm, (s0 + a) / norm, o.laser_origin->x_mm, z_origin);
  }
};

// What each family is started from: the measured geometry.
struct Start {
  double center, width, height;
  int n;  // points fitted
};

// The cut superellipse (a, b, c, n), its bias's sigma from the fit's
// covariance and the unseen half's exponent.
FamilyFit FitCutSuperellipse(const Points& pts, const OcclusionOptions& o, const Start& s0, const Shadow& shadow) {
  const double width = s0.width, height = s0.height;
  const int n = s0.n;
  FamilyFit f;
  f.family = "cut_superellipse";
  f.params = CutSuperellipse::kParams + 1;
  double center = s0.center;
  std::vector<double> p = {width / 2, 0.7 * height, 0.3 * height, 2.5};
  ceres::Problem problem;
  const double rss = Fit<CutSuperellipse>(pts, o.huber_mm, center, p, {0.05 * width, 0.05 * height, 0.0, 1.3},
                                          {2 * width, 2 * height, 0.95 * height, 12.0}, problem);
  if (rss >= 0) {
    f.ok = true;
    f.rss = rss;
    auto bias = [&](const std::vector<double>& q) {
      const CutSuperellipse m{q[0], q[1], std::min(q[2], 0.98 * q[1]), q[3]};
      return m.VisibleArea() + shadow(m.c, center, m.a) - m.TrueArea();
    };
    const CutSuperellipse m{p[0], p[1], std::min(p[2], 0.98 * p[1]), p[3]};
    f.true_area_mm2 = m.TrueArea();
    f.visible_area_mm2 = m.VisibleArea() + shadow(m.c, center, m.a);
    f.bias_mm2 = bias(p);
    f.contact_width_mm = m.ContactWidth();
    f.max_width_mm = 2 * m.a;
    f.widest_height_mm = m.c;
    f.shape = {m.a / m.Height(), m.b / m.Height(), m.c / m.Height(), m.n};
    Eigen::MatrixXd cov;
    if (ParamCovariance(problem, p.data(), 4, rss / std::max(1, n - f.params), cov)) {
      Eigen::VectorXd grad(4);
      for (int k = 0; k < 4; ++k) {
        std::vector<double> q = p;
        const double step = 1e-6 * std::max(1.0, std::abs(p[k]));
        q[k] += step;
        const double up = bias(q);
        q[k] -= 2 * step;
        grad(k) = (up - bias(q)) / (2 * step);
      }
      f.bias_sigma_mm2 = std::sqrt(std::max(0.0, grad.dot(cov * grad)));
    } else {
      f.bias_sigma_mm2 = std::abs(f.bias_mm2);  // no covariance: as large as the bias itself
    }
    // The unseen half need not mirror the seen one: its exponent within
    // +-15 % of the fitted one changes the hidden area by this much (one sigma).
    const double prior = 0.5 * std::abs(m.BottomArea(0.85 * m.n) - m.BottomArea(1.15 * m.n));
    f.bias_sigma_mm2 = std::hypot(f.bias_sigma_mm2, prior);
  }
  return f;
}

// The rounded rectangle (w, H, rt); its bottom radius is not seen.
FamilyFit FitRoundedRectangle(const Points& pts, const OcclusionOptions& o, const Start& s0, const Shadow& shadow) {
  const double width = s0.width, height = s0.height;
  FamilyFit f;
  f.family = "rounded_rectangle";
  f.params = RoundedRectangle::kParams + 1;
  f.constrained = false;
  double center = s0.center;
  std::vector<double> p = {width, height, 0.3 * height};
  ceres::Problem problem;
  const double rss = Fit<RoundedRectangle>(pts, o.huber_mm, center, p, {0.05 * width, 0.05 * height, 0.0},
                                           {2 * width, 2 * height, 0.5 * width}, problem);
  if (rss >= 0) {
    f.ok = true;
    f.rss = rss;
    const double rb_max = std::max(0.0, std::min(p[1] - p[2], p[0] / 2));
    const double k = 2 * (1 - std::numbers::pi / 4);
    // rb uniform on [0, rb_max]: hidden k rb^2 has mean k rb_max^2 / 3 and
    // standard deviation k rb_max^2 (2 / (3 sqrt 5)).
    const double hidden_mean = k * rb_max * rb_max / 3;
    const double hidden_sd = k * rb_max * rb_max * 2 / (3 * std::sqrt(5.0));
    const RoundedRectangle m{p[0], p[1], std::min(p[2], std::min(p[1], p[0] / 2)), 0.0};  // rb: not seen
    const double sh = shadow(p[1] - m.rt, center, p[0] / 2);
    f.visible_area_mm2 = m.VisibleArea() + sh;
    f.bias_mm2 = hidden_mean + sh;
    f.true_area_mm2 = f.visible_area_mm2 - f.bias_mm2;
    f.bias_sigma_mm2 = hidden_sd;
    f.max_width_mm = p[0];
    f.contact_width_mm = std::nan("");
    f.widest_height_mm = std::nan("");
    f.shape = {p[0] / p[1], m.rt / p[1]};
  }
  return f;
}

// The parabolic cap (w, H); nothing hidden.
FamilyFit FitParabolicCap(const Points& pts, const OcclusionOptions& o, const Start& s0) {
  const double width = s0.width, height = s0.height;
  FamilyFit f;
  f.family = "parabolic_cap";
  f.params = ParabolicCap::kParams + 1;
  double center = s0.center;
  std::vector<double> p = {width, height};
  ceres::Problem problem;
  const double rss =
      Fit<ParabolicCap>(pts, o.huber_mm, center, p, {0.05 * width, 0.05 * height}, {3 * width, 2 * height}, problem);
  if (rss >= 0) {
    f.ok = true;
    f.rss = rss;
    const ParabolicCap m{p[0], p[1]};
    f.true_area_mm2 = f.visible_area_mm2 = m.TrueArea();
    f.contact_width_mm = f.max_width_mm = p[0];
    f.shape = {p[0] / p[1]};
  }
  return f;
}

// The families weighed by their BIC: the bias their mixture gives, its
// variance within and between them, and the measured area's own.
void AverageFamilies(const BeadGeometry& g, int n, OcclusionEstimate& est) {
  double best_bic = INFINITY;
  for (FamilyFit& f : est.families)
    if (f.ok) best_bic = std::min(best_bic, f.bic = Bic(f.rss, n, f.params));
  double total = 0;
  for (FamilyFit& f : est.families)
    if (f.ok) total += f.weight = std::exp(-(f.bic - best_bic) / 2);
  if (!(total > 0)) {
    est.note = "no family could be fitted";
    return;
  }
  double mean = 0, unconstrained = 0, best_weight = -1;
  for (FamilyFit& f : est.families) {
    if (!f.ok) continue;
    f.weight /= total;
    mean += f.weight * f.bias_mm2;
    if (!f.constrained) unconstrained += f.weight;
    if (f.weight > best_weight) best_weight = f.weight, est.family = f.family;
  }
  double var = 0;
  for (const FamilyFit& f : est.families)
    if (f.ok) var += f.weight * (f.bias_sigma_mm2 * f.bias_sigma_mm2 + (f.bias_mm2 - mean) * (f.bias_mm2 - mean));
  est.ok = true;
  est.bias_mm2 = mean;
  // The measured area's own uncertainty adds to the bias's.
  est.sigma_mm2 = std::sqrt(var + g.area_sigma_mm2 * g.area_sigma_mm2);
  est.constrained = unconstrained < 0.5;
  est.corrected_area_mm2 = g.area_mm2 - mean;
  if (!est.constrained)
    est.note = "the hidden part is not constrained by the data: the best shape hides an undercut it cannot show";
}

}  // namespace

OcclusionEstimate EstimateOcclusion(const ProfileView& view, const BeadGeometry& g, const OcclusionOptions& o) {
  OcclusionEstimate est;
  if (!g.valid()) {
    est.note = "profile not measured";
    return est;
  }
  const Points pts = SeenPoints(view, g, o.margin_mm);
  const int n = static_cast<int>(pts.u.size());
  if (n < 12) {
    est.note = "too few points on the bead to fit a shape";
    return est;
  }
  const double norm = std::sqrt(1 + g.reference.slope * g.reference.slope);
  const Start start{g.center_x_mm * norm, g.width_mm, g.height_mm, n};
  const Shadow shadow{g, o, norm};
  est.families = {FitCutSuperellipse(pts, o, start, shadow), FitRoundedRectangle(pts, o, start, shadow),
                  FitParabolicCap(pts, o, start)};
  AverageFamilies(g, n, est);
  return est;
}

PooledOcclusion PoolOcclusion(std::size_t count, const std::function<ProfileView(std::size_t)>& view,
                              const std::vector<BeadGeometry>& geometry, const OcclusionOptions& options,
                              int max_fits) {
  std::vector<std::size_t> valid;
  for (std::size_t i = 0; i < count; ++i)
    if (geometry[i].valid()) valid.push_back(i);
  std::vector<OcclusionEstimate> fits;
  std::vector<BeadGeometry> fitted;
  for (const std::size_t rank : PoolRanks(valid.size(), max_fits)) {
    const std::size_t i = valid[rank];
    fitted.push_back(geometry[i]);
    fits.push_back(EstimateOcclusion(view(i), geometry[i], options));
  }
  return PoolFromFits(fits, fitted);
}

}  // namespace bead::occlusion
