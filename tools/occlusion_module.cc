// bead-occlusion-fit.so: occlusion::EstimateOcclusion (bead::occlusion,
// Ceres) for the programs that load it on demand (tools/occlusion_module.h).
// Only these two functions are exported; no exception leaves the module.
#include <exception>
#include <string>

#include "libbead/occlusion/occlusion_fit.h"
#include "tools/occlusion_module.h"

extern "C" __attribute__((visibility("default"))) const char* bead_occlusion_module_abi() {
  static const std::string abi = bead::tools::OcclusionModuleAbi();
  return abi.c_str();
}

extern "C" __attribute__((visibility("default"))) int bead_occlusion_estimate(
    const bead::ProfileView* view, const bead::BeadGeometry* geometry, const bead::occlusion::OcclusionOptions* options,
    bead::occlusion::OcclusionEstimate* out, std::string* error) {
  try {
    *out = bead::occlusion::EstimateOcclusion(*view, *geometry, *options);
    return 0;
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "the occlusion fit failed (an unknown exception)";
  }
  return 1;
}
