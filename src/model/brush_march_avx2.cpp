// The marcher's x step on packs of four strips (AVX2 + FMA). This file alone is compiled with
// -mavx2 -mfma (cmake/modules.cmake) and is only called where the CPU has both (fastestAdvance()).
// Everything here has internal linkage and uses no inline function of the standard library, so no
// AVX2 code can stand in for a baseline copy of a shared inline function at link time.
#include <immintrin.h>

#include "brush_march.h"

// glibc's libmvec (x86_64, glibc >= 2.22; log1p >= 2.35): vector exp/log/log1p, <= 4 ulp, without
// -ffast-math. Names follow the x86 vector function ABI: 'd' = AVX2, 4 lanes, one vector argument.
extern "C" {
__m256d _ZGVdN4v_exp(__m256d x);
__m256d _ZGVdN4v_log(__m256d x);
__m256d _ZGVdN4v_log1p(__m256d x);
}

namespace tread_wear {
namespace march {
namespace {

/// Four doubles (four strips).
struct F64x4 {
  __m256d v;
  F64x4() = default;
  F64x4(double x) : v(_mm256_set1_pd(x)) {}  // NOLINT: a scalar is broadcast, as for double
  F64x4(__m256d x) : v(x) {}                  // NOLINT
};

/// Lane mask of an F64x4 comparison (all bits set in a true lane).
struct Mask4 {
  __m256d m;
};

inline F64x4 operator+(F64x4 a, F64x4 b) { return _mm256_add_pd(a.v, b.v); }
inline F64x4 operator-(F64x4 a, F64x4 b) { return _mm256_sub_pd(a.v, b.v); }
inline F64x4 operator*(F64x4 a, F64x4 b) { return _mm256_mul_pd(a.v, b.v); }
inline F64x4 operator/(F64x4 a, F64x4 b) { return _mm256_div_pd(a.v, b.v); }
inline F64x4 operator-(F64x4 a) { return _mm256_xor_pd(a.v, _mm256_set1_pd(-0.0)); }
// Ordered comparisons are false with a NaN, as for double; != is true with a NaN, as for double.
inline Mask4 operator<(F64x4 a, F64x4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
inline Mask4 operator<=(F64x4 a, F64x4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)}; }
inline Mask4 operator>(F64x4 a, F64x4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
inline Mask4 operator>=(F64x4 a, F64x4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GE_OQ)}; }
inline Mask4 operator==(F64x4 a, F64x4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_EQ_OQ)}; }
inline Mask4 operator!=(F64x4 a, F64x4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_NEQ_UQ)}; }
inline Mask4 operator&(Mask4 a, Mask4 b) { return {_mm256_and_pd(a.m, b.m)}; }
inline Mask4 operator|(Mask4 a, Mask4 b) { return {_mm256_or_pd(a.m, b.m)}; }
inline Mask4 operator!(Mask4 a) { return {_mm256_xor_pd(a.m, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))}; }

inline bool any(Mask4 m) { return _mm256_movemask_pd(m.m) != 0; }
inline F64x4 select(Mask4 m, F64x4 a, F64x4 b) { return _mm256_blendv_pd(b.v, a.v, m.m); }
inline F64x4 vexp(F64x4 x) { return _ZGVdN4v_exp(x.v); }
inline F64x4 vlog(F64x4 x) { return _ZGVdN4v_log(x.v); }
inline F64x4 vlog1p(F64x4 x) { return _ZGVdN4v_log1p(x.v); }
inline F64x4 vsqrt(F64x4 x) { return _mm256_sqrt_pd(x.v); }
inline F64x4 vabs(F64x4 x) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), x.v); }
inline F64x4 vmin(F64x4 a, F64x4 b) { return _mm256_min_pd(a.v, b.v); }
inline F64x4 vmax(F64x4 a, F64x4 b) { return _mm256_max_pd(a.v, b.v); }

template <>
struct LaneTraits<F64x4> {
  using Mask = Mask4;
  static constexpr int kWidth = 4;
  static F64x4 load(const double* p) { return _mm256_loadu_pd(p); }
  static void store(double* p, F64x4 v) { _mm256_storeu_pd(p, v.v); }
  /// Lanes [0, n) true.
  static Mask4 firstLanes(int n) {
    const __m256d lane = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
    return {_mm256_cmp_pd(lane, _mm256_set1_pd(n), _CMP_LT_OQ)};
  }
  static Mask4 none() { return {_mm256_setzero_pd()}; }
  static int maxLane(F64x4 v) {
    const __m128d half = _mm_max_pd(_mm256_castpd256_pd128(v.v), _mm256_extractf128_pd(v.v, 1));
    return static_cast<int>(_mm_cvtsd_f64(_mm_max_sd(half, _mm_unpackhi_pd(half, half))));
  }
  static long sumLanes(F64x4 v) {
    const __m128d half = _mm_add_pd(_mm256_castpd256_pd128(v.v), _mm256_extractf128_pd(v.v, 1));
    return static_cast<long>(_mm_cvtsd_f64(_mm_add_sd(half, _mm_unpackhi_pd(half, half))));
  }
};

}  // namespace

void advanceAvx2(const StepArgs& args, int first, int count, const PathState& from, PathState* to, NodeLanes* out,
                 RootCounts* counts) {
  advanceInPacks<F64x4>(args, first, count, from, to, out, counts);
}

}  // namespace march
}  // namespace tread_wear
