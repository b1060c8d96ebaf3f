// The occlusion fit, loaded when first needed. It needs Ceres, and Ceres
// brings glog, SuiteSparse and BLAS: twenty shared libraries, about 11 ms
// before main(). The programs that otherwise need none of it (bead-measure,
// bead-flow, bead-batch) take the fit from a module, bead-occlusion-fit.so
// (tools/occlusion_module.cc), loaded the first time a fit runs: beside the
// program in the build tree, in LIBDIR/bead when installed. A module from
// another build of bead is refused, saying so.
#pragma once

#include <string>

#include "libbead/occlusion/occlusion_fit.h"

namespace bead::tools {

// occlusion::EstimateOcclusion from the module (an occlusion::Estimator);
// throws bead::Error naming the paths tried when it cannot be loaded.
occlusion::OcclusionEstimate EstimateOcclusionOnDemand(const ProfileView& view, const BeadGeometry& geometry,
                                                       const occlusion::OcclusionOptions& options);

// What the module and its loader must agree on: bead's version and the
// sizes of the types that cross between them.
inline std::string OcclusionModuleAbi() {
  return std::string(BEAD_VERSION) + "/" + std::to_string(sizeof(ProfileView)) + "/" +
         std::to_string(sizeof(BeadGeometry)) + "/" + std::to_string(sizeof(occlusion::OcclusionOptions)) + "/" +
         std::to_string(sizeof(occlusion::OcclusionEstimate)) + "/" + std::to_string(sizeof(std::string));
}

}  // namespace bead::tools
