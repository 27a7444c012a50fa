#include "brush_march.h"

namespace tread_wear {
namespace march {

void advanceScalar(const StepArgs& args, int first, int count, const PathState& from, PathState* to, NodeLanes* out,
                   RootCounts* counts) {
  advanceInPacks<double>(args, first, count, from, to, out, counts);
}

AdvanceFunction fastestAdvance(int max_lanes) {
#ifdef TREAD_WEAR_SIMD_MARCHER
  __builtin_cpu_init();
  if (max_lanes >= 4 && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return advanceAvx2;
  if (max_lanes >= 2) return advanceSse2;
#endif
  (void)max_lanes;
  return advanceScalar;
}

}  // namespace march
}  // namespace tread_wear
