#include "brush_march.h"

#include <algorithm>

namespace tread_wear {
namespace march {

void PathState::copyFrom(const PathState& from, int n) {
  for (auto field : {&PathState::dlx, &PathState::dly, &PathState::ux, &PathState::uy, &PathState::dlx_p,
                     &PathState::dly_p, &PathState::ux_p, &PathState::uy_p, &PathState::z, &PathState::z_p,
                     &PathState::sliding, &PathState::sliding_p})
    std::copy_n(from.*field, n, this->*field);
}

void PathState::copyStrip(const PathState& from, int j) {
  for (auto field : {&PathState::dlx, &PathState::dly, &PathState::ux, &PathState::uy, &PathState::dlx_p,
                     &PathState::dly_p, &PathState::ux_p, &PathState::uy_p, &PathState::z, &PathState::z_p,
                     &PathState::sliding, &PathState::sliding_p})
    (this->*field)[j] = (from.*field)[j];
}

void advanceScalar(const StepArgs& args, int first, int count, PathState* state, NodeLanes* out, RootCounts* counts) {
  for (int j = first; j < first + count; ++j) advancePack<double>(args, j, 1, state, out, counts);
}

AdvanceFunction fastestAdvance() {
#ifdef TREAD_WEAR_AVX2_MARCHER
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return advanceAvx2;
#endif
  return advanceScalar;
}

}  // namespace march
}  // namespace tread_wear
