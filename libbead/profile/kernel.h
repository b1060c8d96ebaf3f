// The per-profile kernel: point_set.cc, reference_line.cc, bead_geometry.cc
// and kernel_entry.cc, built twice from the same sources (libbead/CMakeLists.txt):
// once for AVX2 with FMA (eight floats a register, one-instruction mask
// reductions, fused multiply-adds) in namespace bead::avx2, once for the
// x86-64 baseline (SSE2) in bead::baseline. The public functions
// (entry_points.cc, ProfileProcessor) run the one this processor can, chosen
// once: AVX2 where the processor has AVX2 and FMA. Sums reordered or fused
// round differently in the last bits of a float on the two builds; nothing
// else differs (tested).
#pragma once

#include <cstddef>

#include "libbead/core/rig.h"
#include "libbead/profile/bead_geometry.h"
#include "libbead/profile/point_set.h"
#include "libbead/core/profile_view.h"
#include "libbead/profile/profile_processor.h"
#include "libbead/profile/reference_line.h"
#include "libbead/profile/workspace.h"

namespace bead {

struct ProfileKernel {
  const char* name;
  PointSet (*prepare)(const ProfileView&, ProfileWorkspace&);
  std::size_t (*count_finite_z)(const PointSet&, std::size_t, std::size_t);
  ReferenceLine (*fit)(const PointSet&, const ReferenceArea&, const ReferenceArea&, const ReferenceLineOptions&,
                       ProfileWorkspace&);
  BeadGeometry (*measure)(const PointSet&, const ReferenceLine&, const ReferenceArea&, const ReferenceArea&,
                          const BeadOptions&, ProfileWorkspace&);
  // All three stages of one profile.
  BeadGeometry (*process)(const ProfileView&, const ReferenceArea&, const ReferenceArea&, const ProfileOptions&,
                          ProfileWorkspace&);
};

// The baseline kernel (always built).
const ProfileKernel& BaselineKernel();
// The AVX2 kernel, or nullptr when this build or this processor has none.
const ProfileKernel* Avx2Kernel();
// The kernel the public functions run.
const ProfileKernel& ActiveKernel();

// Inside the kernel's sources: its own functions, called directly.
#ifdef BEAD_KERNEL
namespace BEAD_KERNEL {
PointSet PreparePoints(const ProfileView& view, ProfileWorkspace& workspace);
std::size_t CountFiniteZ(const PointSet& points, std::size_t begin, std::size_t end);
ReferenceLine FitReferenceLine(const PointSet& points, const ReferenceArea& left, const ReferenceArea& right,
                               const ReferenceLineOptions& options, ProfileWorkspace& workspace);
BeadGeometry MeasureBead(const PointSet& points, const ReferenceLine& line, const ReferenceArea& left,
                         const ReferenceArea& right, const BeadOptions& options, ProfileWorkspace& workspace);
const ProfileKernel& Kernel();
}  // namespace BEAD_KERNEL
#endif

}  // namespace bead
