// The marcher's x step on packs of two strips (SSE2, the x86-64 baseline): for CPUs without AVX2.
#include <emmintrin.h>

#include "brush_march.h"

// glibc's libmvec (x86_64, glibc >= 2.22; log1p >= 2.35): vector exp/log/log1p, <= 4 ulp, without
// -ffast-math. Names follow the x86 vector function ABI: 'b' = SSE2, 2 lanes, one vector argument.
extern "C" {
__m128d _ZGVbN2v_exp(__m128d x);
__m128d _ZGVbN2v_log(__m128d x);
__m128d _ZGVbN2v_log1p(__m128d x);
}

namespace tread_wear {
namespace march {
namespace {

/// Two doubles (two strips).
struct F64x2 {
  __m128d v;
  F64x2() = default;
  F64x2(double x) : v(_mm_set1_pd(x)) {}  // NOLINT: a scalar is broadcast, as for double
  F64x2(__m128d x) : v(x) {}                  // NOLINT
};

/// Lane mask of an F64x2 comparison (all bits set in a true lane).
struct Mask2 {
  __m128d m;
};

inline F64x2 operator+(F64x2 a, F64x2 b) { return _mm_add_pd(a.v, b.v); }
inline F64x2 operator-(F64x2 a, F64x2 b) { return _mm_sub_pd(a.v, b.v); }
inline F64x2 operator*(F64x2 a, F64x2 b) { return _mm_mul_pd(a.v, b.v); }
inline F64x2 operator/(F64x2 a, F64x2 b) { return _mm_div_pd(a.v, b.v); }
inline F64x2 operator-(F64x2 a) { return _mm_xor_pd(a.v, _mm_set1_pd(-0.0)); }
// Ordered comparisons are false with a NaN, as for double; != is true with a NaN, as for double.
inline Mask2 operator<(F64x2 a, F64x2 b) { return {_mm_cmplt_pd(a.v, b.v)}; }
inline Mask2 operator<=(F64x2 a, F64x2 b) { return {_mm_cmple_pd(a.v, b.v)}; }
inline Mask2 operator>(F64x2 a, F64x2 b) { return {_mm_cmpgt_pd(a.v, b.v)}; }
inline Mask2 operator>=(F64x2 a, F64x2 b) { return {_mm_cmpge_pd(a.v, b.v)}; }
inline Mask2 operator==(F64x2 a, F64x2 b) { return {_mm_cmpeq_pd(a.v, b.v)}; }
inline Mask2 operator!=(F64x2 a, F64x2 b) { return {_mm_cmpneq_pd(a.v, b.v)}; }
inline Mask2 operator&(Mask2 a, Mask2 b) { return {_mm_and_pd(a.m, b.m)}; }
inline Mask2 operator|(Mask2 a, Mask2 b) { return {_mm_or_pd(a.m, b.m)}; }
inline Mask2 operator!(Mask2 a) { return {_mm_xor_pd(a.m, _mm_castsi128_pd(_mm_set1_epi64x(-1)))}; }

inline bool any(Mask2 m) { return _mm_movemask_pd(m.m) != 0; }
// SSE2 has no blend: (m and a) or (not m and b).
inline F64x2 select(Mask2 m, F64x2 a, F64x2 b) { return _mm_or_pd(_mm_and_pd(m.m, a.v), _mm_andnot_pd(m.m, b.v)); }
inline F64x2 vexp(F64x2 x) { return _ZGVbN2v_exp(x.v); }
inline F64x2 vlog(F64x2 x) { return _ZGVbN2v_log(x.v); }
inline F64x2 vlog1p(F64x2 x) { return _ZGVbN2v_log1p(x.v); }
inline F64x2 vsqrt(F64x2 x) { return _mm_sqrt_pd(x.v); }
inline F64x2 vabs(F64x2 x) { return _mm_andnot_pd(_mm_set1_pd(-0.0), x.v); }
inline F64x2 vmin(F64x2 a, F64x2 b) { return _mm_min_pd(a.v, b.v); }
inline F64x2 vmax(F64x2 a, F64x2 b) { return _mm_max_pd(a.v, b.v); }

template <>
struct LaneTraits<F64x2> {
  using Mask = Mask2;
  static constexpr int kWidth = 2;
  static F64x2 load(const double* p) { return _mm_loadu_pd(p); }
  static void store(double* p, F64x2 v) { _mm_storeu_pd(p, v.v); }
  /// Lanes [0, n) true.
  static Mask2 firstLanes(int n) { return {_mm_cmplt_pd(_mm_set_pd(1.0, 0.0), _mm_set1_pd(n))}; }
  static Mask2 none() { return {_mm_setzero_pd()}; }
  static int maxLane(F64x2 v) { return static_cast<int>(_mm_cvtsd_f64(_mm_max_sd(v.v, _mm_unpackhi_pd(v.v, v.v)))); }
  static long sumLanes(F64x2 v) { return static_cast<long>(_mm_cvtsd_f64(_mm_add_sd(v.v, _mm_unpackhi_pd(v.v, v.v)))); }
};

}  // namespace

void advanceSse2(const StepArgs& args, int first, int count, const PathState& from, PathState* to, NodeLanes* out,
                 RootCounts* counts) {
  advanceInPacks<F64x2>(args, first, count, from, to, out, counts);
}

}  // namespace march
}  // namespace tread_wear
