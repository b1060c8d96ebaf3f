// The part kernel this processor runs (part_kernel.h), chosen once.
#include "libbead/part/part_kernel.h"

namespace bead::part {

#ifdef BEAD_AVX2_KERNEL
namespace avx2 {
const PartKernel& PartKernelBuild();
}  // namespace avx2
#endif
namespace baseline {
const PartKernel& PartKernelBuild();
}  // namespace baseline

const PartKernel& BaselinePartKernel() { return baseline::PartKernelBuild(); }

const PartKernel& ActivePartKernel() {
#ifdef BEAD_AVX2_KERNEL
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (avx2) return avx2::PartKernelBuild();
#endif
  return BaselinePartKernel();
}

}  // namespace bead::part
