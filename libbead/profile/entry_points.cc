// The public per-profile functions, each running the kernel chosen for
// this processor (kernel.h), and the small helpers of their types.
#include <cmath>

#include "libbead/profile/kernel.h"

namespace bead {

#ifdef BEAD_AVX2_KERNEL
namespace avx2 {
const ProfileKernel& Kernel();
}
#endif
namespace baseline {
const ProfileKernel& Kernel();
}

const ProfileKernel& BaselineKernel() { return baseline::Kernel(); }

const ProfileKernel* Avx2Kernel() {
#ifdef BEAD_AVX2_KERNEL
  static const bool supported = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (supported) return &avx2::Kernel();
#endif
  return nullptr;
}

const ProfileKernel& ActiveKernel() {
  static const ProfileKernel& kernel = Avx2Kernel() ? *Avx2Kernel() : BaselineKernel();
  return kernel;
}

PointSet PreparePoints(const ProfileView& view, ProfileWorkspace& workspace) {
  return ActiveKernel().prepare(view, workspace);
}

std::size_t CountFiniteZ(const PointSet& points, std::size_t begin, std::size_t end) {
  return ActiveKernel().count_finite_z(points, begin, end);
}

ReferenceLine FitReferenceLine(const PointSet& points, const ReferenceArea& left, const ReferenceArea& right,
                               const ReferenceLineOptions& options, ProfileWorkspace& workspace) {
  return ActiveKernel().fit(points, left, right, options, workspace);
}

ReferenceLine FitReferenceLine(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                               const ReferenceLineOptions& options, ProfileWorkspace& workspace) {
  const ProfileKernel& kernel = ActiveKernel();
  return kernel.fit(kernel.prepare(view, workspace), left, right, options, workspace);
}

BeadGeometry MeasureBead(const PointSet& points, const ReferenceLine& line, const ReferenceArea& left,
                         const ReferenceArea& right, const BeadOptions& options, ProfileWorkspace& workspace) {
  return ActiveKernel().measure(points, line, left, right, options, workspace);
}

double ReferenceLine::HeightAt(double x_mm, double z_mm) const {
  return (z_mm - intercept_mm - slope * x_mm) / std::sqrt(1.0 + slope * slope);
}

const char* StatusName(ProfileStatus status) {
  switch (status) {
    case ProfileStatus::kValid:
      return "valid";
    case ProfileStatus::kTooFewPoints:
      return "too_few_points";
    case ProfileStatus::kNoReference:
      return "no_reference";
    case ProfileStatus::kNoBead:
      return "no_bead";
    case ProfileStatus::kBeadEdgeNotSeen:
      return "bead_edge_not_seen";
    case ProfileStatus::kBeadInReferenceArea:
      return "bead_in_reference_area";
  }
  return "unknown";
}

}  // namespace bead
