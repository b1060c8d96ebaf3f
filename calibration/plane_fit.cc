#include "calibration/plane_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include "libbead/core/error.h"
#include "libbead/core/median.h"

namespace bead::calibration {
namespace {

struct PlaneDistance {
  cv::Point3d p;
  template <typename T>
  bool operator()(const T* n, const T* d, T* r) const {
    r[0] = n[0] * p.x + n[1] * p.y + n[2] * p.z + d[0];
    return true;
  }
};

cv::Vec4d LeastSquares(const std::vector<cv::Point3d>& points, const std::vector<double>& weight) {
  cv::Point3d c(0, 0, 0);
  double w_sum = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) c += weight[i] * points[i], w_sum += weight[i];
  c *= 1.0 / w_sum;
  cv::Matx33d scatter = cv::Matx33d::zeros();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const cv::Vec3d q = cv::Vec3d(points[i] - c);
    scatter += weight[i] * q * q.t();
  }
  cv::Matx31d values;
  cv::Matx33d vectors;
  cv::eigen(scatter, values, vectors);  // descending: the last row is the normal
  if (!(values(1) > 1e-9 * values(0)))
    throw Error(
        "the stripe points lie on one line: the laser plane is undetermined (the board needs "
        "different heights or tilts across the views)");
  const cv::Vec3d n(vectors(2, 0), vectors(2, 1), vectors(2, 2));
  return {n[0], n[1], n[2], -n.dot(cv::Vec3d(c))};
}

double RobustSigma(const std::vector<cv::Point3d>& points, const cv::Vec4d& plane) {
  std::vector<double> r;
  r.reserve(points.size());
  for (const cv::Point3d& p : points) r.push_back(std::abs(Distance(plane, p)));
  return 1.4826 * MedianInPlace(r.data(), r.size());
}

}  // namespace

double Distance(const cv::Vec4d& plane, const cv::Point3d& p) {
  return plane[0] * p.x + plane[1] * p.y + plane[2] * p.z + plane[3];
}

PlaneFit FitPlaneRobust(const std::vector<cv::Point3d>& points) {
  if (points.size() < 10)
    throw Error("only " + std::to_string(points.size()) + " stripe points on the boards: a plane needs 10 or more");
  PlaneFit fit;
  fit.plane = LeastSquares(points, std::vector<double>(points.size(), 1.0));
  double n[3] = {fit.plane[0], fit.plane[1], fit.plane[2]}, d = fit.plane[3];
  for (int round = 0; round < 3; ++round) {
    const double sigma = std::max(RobustSigma(points, {n[0], n[1], n[2], d}), 1e-4);
    ceres::Problem problem;
    for (const cv::Point3d& p : points)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PlaneDistance, 1, 3, 1>(new PlaneDistance{p}),
                               new ceres::CauchyLoss(sigma), n, &d);
    problem.SetManifold(n, new ceres::SphereManifold<3>());
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = 100;
    options.function_tolerance = 1e-14;
    options.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
  }
  const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double sign = d < 0.0 ? -1.0 : 1.0;
  fit.plane = cv::Vec4d(n[0], n[1], n[2], d) * (sign / norm);
  fit.sigma_mm = RobustSigma(points, fit.plane);
  const double cut = std::max(3.0 * fit.sigma_mm, 0.01);
  fit.inlier.assign(points.size(), false);
  double ss = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double r = Distance(fit.plane, points[i]);
    if (std::abs(r) <= cut) fit.inlier[i] = true, ++fit.inliers, ss += r * r;
  }
  fit.rms_mm = fit.inliers ? std::sqrt(ss / fit.inliers) : 0.0;
  return fit;
}

cv::Matx33d PlaneHomography(const cv::Matx33d& camera, const cv::Vec4d& plane, const cv::Vec3d& origin,
                            const cv::Vec3d& e_x, const cv::Vec3d& e_z) {
  const cv::Vec3d n(plane[0], plane[1], plane[2]);
  const double d = plane[3];
  cv::Matx33d m;
  for (int c = 0; c < 3; ++c) {
    m(0, c) = -d * e_x[c] - e_x.dot(origin) * n[c];
    m(1, c) = -d * e_z[c] - e_z.dot(origin) * n[c];
    m(2, c) = n[c];
  }
  cv::Matx33d h = m * camera.inv();
  return h * (1.0 / h(2, 2));
}

}  // namespace bead::calibration
