#include "brush_march.h"

namespace tread_wear {
namespace march {

void advanceScalar(const StepArgs& args, int first, int count, const PathState& from, PathState* to, NodeLanes* out,
                   RootCounts* counts) {
  for (int j = first; j < first + count; ++j) advancePack<double>(args, j, 1, from, to, out, counts);
}

AdvanceFunction fastestAdvance() {
#ifdef TREAD_WEAR_SIMD_MARCHER
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return advanceAvx2;
  return advanceSse2;
#else
  return advanceScalar;
#endif
}

}  // namespace march
}  // namespace tread_wear
