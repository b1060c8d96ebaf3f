// Loads bead-occlusion-fit.so (tools/occlusion_module.h).
#include <dlfcn.h>

#include <mutex>

#include "libbead/core/error.h"
#include "tools/occlusion_module.h"
#include "tools/own_folder.h"

namespace bead::tools {
namespace {

// tools/occlusion_module.cc
using Entry = int (*)(const ProfileView*, const BeadGeometry*, const occlusion::OcclusionOptions*,
                      occlusion::OcclusionEstimate*, std::string*);
using Abi = const char* (*)();
constexpr const char* kModule = "bead-occlusion-fit.so";

Entry Load() {
  const std::string folder = OwnFolder("bead");
  const std::string paths[] = {folder + "/" + kModule, folder + "/" BEAD_MODULE_FROM_BIN "/" + kModule};
  std::string tried;
  for (const std::string& path : paths) {
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      tried += "; " + (why ? std::string(why) : path + ": cannot be loaded");
      continue;
    }
    const auto abi = reinterpret_cast<Abi>(dlsym(handle, "bead_occlusion_module_abi"));
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, "bead_occlusion_estimate"));
    if (abi == nullptr || entry == nullptr || OcclusionModuleAbi() != abi()) {
      tried += "; " + path + ": built from another build of bead (" + (abi ? abi() : "no version") + ", this program " +
               OcclusionModuleAbi() + ")";
      dlclose(handle);
      continue;
    }
    return entry;
  }
  throw Error("the occlusion fit (" + std::string(kModule) +
              ", Ceres) cannot be loaded; reinstall bead, or run with --occlusion none" + tried);
}

}  // namespace

occlusion::OcclusionEstimate EstimateOcclusionOnDemand(const ProfileView& view, const BeadGeometry& geometry,
                                                       const occlusion::OcclusionOptions& options) {
  static std::mutex mutex;
  static Entry entry = nullptr;
  Entry e;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (entry == nullptr) entry = Load();  // a failure is thrown, and tried again on the next call
    e = entry;
  }
  occlusion::OcclusionEstimate out;
  std::string error;
  if (e(&view, &geometry, &options, &out, &error) != 0) throw Error(error);
  return out;
}

}  // namespace bead::tools
