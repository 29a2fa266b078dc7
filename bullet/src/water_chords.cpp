// The vertical chords of a convex polyhedron along a row of points (chord_row,
// water_shape.h). A floating body's displacement asks them for every sub-sample row under
// it every substep (a wheel: 34 faces over rows of some 15 points), the largest part of the
// water coupling's cost, so the points go several to a vector register: four with AVX
// where the CPU has it (two registers a turn), else two with SSE2, else one by one. Each
// point gets the operations the scalar loop gives it, in its order: rest = base + k step
// (k exact as a double), z = rest times 1 / n_z, then the min or max with the chord's end
// so far; IEEE arithmetic rounds each lane as it would alone and min_pd / max_pd pick as
// the scalar comparisons do (_mm_min_pd(z, h) is z < h ? z : h), so every path gives the
// same bits.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "shore/core/cpu_features.h"
#if defined(SHORE_X86_DISPATCH) && !defined(SHORE_CHORDS_NO_AVX)  // (a test builds the other paths)
#define SHORE_CHORDS_AVX 1
#include <immintrin.h>
#endif

#include "water_shape.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace water_detail {

namespace {

/// What one face does to the chords: a face looking up caps them (min into hi), one looking
/// down floors them (max into lo), an upright one empties the points outside it (lo = +inf
/// where rest < 0).
enum class Narrow { upper, lower, upright };

template <Narrow kNarrow>
void narrow_one(double rest, double inv, double* __restrict lo, double* __restrict hi, int k) {
  if constexpr (kNarrow == Narrow::upright) {
    if (rest < 0.0) lo[k] = std::numeric_limits<double>::infinity();
  } else if constexpr (kNarrow == Narrow::upper) {
    const double z = rest * inv;
    hi[k] = z < hi[k] ? z : hi[k];
  } else {
    const double z = rest * inv;
    lo[k] = z > lo[k] ? z : lo[k];
  }
}

/// The points [k, n) one by one.
template <Narrow kNarrow>
void narrow_scalar(double base, double step, double inv, int k, int n, double* __restrict lo, double* __restrict hi) {
  for (; k < n; ++k) narrow_one<kNarrow>(base + k * step, inv, lo, hi, k);
}

#if defined(__SSE2__)
template <Narrow kNarrow>
__m128d narrow_two(__m128d rest, __m128d inv, __m128d v) {
  if constexpr (kNarrow == Narrow::upright) {
    const __m128d below = _mm_cmplt_pd(rest, _mm_setzero_pd());
    return _mm_or_pd(_mm_and_pd(below, _mm_set1_pd(std::numeric_limits<double>::infinity())), _mm_andnot_pd(below, v));
  } else if constexpr (kNarrow == Narrow::upper) {
    return _mm_min_pd(_mm_mul_pd(rest, inv), v);
  } else {
    return _mm_max_pd(_mm_mul_pd(rest, inv), v);
  }
}

/// Two points to a register, two registers a turn, the last few one by one.
template <Narrow kNarrow>
void narrow_sse2(double base, double step, double inv, int n, double* __restrict lo, double* __restrict hi) {
  double* out = kNarrow == Narrow::upper ? hi : lo;
  const __m128d b = _mm_set1_pd(base), s = _mm_set1_pd(step), r = _mm_set1_pd(inv), four = _mm_set1_pd(4.0);
  __m128d k0 = _mm_set_pd(1.0, 0.0), k1 = _mm_set_pd(3.0, 2.0);
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m128d rest0 = _mm_add_pd(b, _mm_mul_pd(k0, s)), rest1 = _mm_add_pd(b, _mm_mul_pd(k1, s));
    _mm_storeu_pd(out + k, narrow_two<kNarrow>(rest0, r, _mm_loadu_pd(out + k)));
    _mm_storeu_pd(out + k + 2, narrow_two<kNarrow>(rest1, r, _mm_loadu_pd(out + k + 2)));
    k0 = _mm_add_pd(k0, four), k1 = _mm_add_pd(k1, four);
  }
  narrow_scalar<kNarrow>(base, step, inv, k, n, lo, hi);
}
#endif

#if defined(SHORE_CHORDS_AVX)
/// base + k step for four points k.
__attribute__((target("avx"))) inline __m256d rest(__m256d base, __m256d step, __m256d k) {
  return _mm256_add_pd(base, _mm256_mul_pd(k, step));
}

/// The row by blocks of eight points, each block seeing every face with its chord ends held
/// in registers (a face's terms broadcast once for the eight). The faces go by what they do
/// (each kind in face order): the caps (min into hi), then the floors (max into lo), then
/// the upright ones; a point's hi sees the caps in the scalar loop's order, and so does its
/// lo the floors, and an upright face that empties the point leaves lo = +inf whenever it
/// comes (no later max moves +inf), so the same bits. Points past the row are masked off.
/// kWiden: a and b are an envelope's lower and upper ends, widened by the chord where the
/// point is inside (lo < hi: a = min(a, lo), b = max(b, hi), as widen_by_chords says), the
/// chord itself started at -inf / +inf in registers; else a and b are lo and hi, narrowed.
template <bool kWiden>
__attribute__((target("avx"))) void chord_row_avx(const WorldPlanes& p, double x0, double dx, int n, double y,
                                                  double* __restrict a, double* __restrict b) {
  const std::size_t faces = p.n.size();
  std::vector<double>& t = p.row_terms;  // base, step, 1 / n_z of each face, by kind
  t.resize(9 * faces);
  double *caps = t.data(), *floors = caps + 3 * faces, *upright = floors + 3 * faces;
  double *cap = caps, *floor = floors, *wall = upright;
  for (std::size_t f = 0; f < faces; ++f) {
    const Vec3 nf = p.n[f];
    const double base = p.d[f] - nf.y * y - nf.x * x0, step = -nf.x * dx;  // rest(k) = base + k step: n_z z <= rest
    double*& to = std::abs(nf.z) < 1e-12 ? wall : nf.z > 0.0 ? cap : floor;
    to[0] = base, to[1] = step, to[2] = std::abs(nf.z) < 1e-12 ? 0.0 : 1.0 / nf.z;
    to += 3;
  }
  const __m256d infinity = _mm256_set1_pd(std::numeric_limits<double>::infinity()),
                minus_infinity = _mm256_set1_pd(-std::numeric_limits<double>::infinity()), eight = _mm256_set1_pd(8.0),
                count = _mm256_set1_pd(double(n)), zero = _mm256_setzero_pd();
  __m256d k0 = _mm256_set_pd(3.0, 2.0, 1.0, 0.0), k1 = _mm256_set_pd(7.0, 6.0, 5.0, 4.0);
  for (int i = 0; i < n; i += 8) {
    const bool second = i + 4 < n;  // the second four has a point in the row
    const __m256i in0 = _mm256_castpd_si256(_mm256_cmp_pd(k0, count, _CMP_LT_OQ));
    const __m256i in1 = _mm256_castpd_si256(_mm256_cmp_pd(k1, count, _CMP_LT_OQ));
    const __m256d a0 = _mm256_maskload_pd(a + i, in0), b0 = _mm256_maskload_pd(b + i, in0);
    const __m256d a1 = second ? _mm256_maskload_pd(a + i + 4, in1) : zero;
    const __m256d b1 = second ? _mm256_maskload_pd(b + i + 4, in1) : zero;
    __m256d l0 = kWiden ? minus_infinity : a0, h0 = kWiden ? infinity : b0;
    __m256d l1 = kWiden ? minus_infinity : a1, h1 = kWiden ? infinity : b1;
    for (const double* c = caps; c != cap; c += 3) {
      const __m256d base = _mm256_broadcast_sd(c), step = _mm256_broadcast_sd(c + 1), inv = _mm256_broadcast_sd(c + 2);
      h0 = _mm256_min_pd(_mm256_mul_pd(rest(base, step, k0), inv), h0);
      h1 = _mm256_min_pd(_mm256_mul_pd(rest(base, step, k1), inv), h1);
    }
    for (const double* c = floors; c != floor; c += 3) {
      const __m256d base = _mm256_broadcast_sd(c), step = _mm256_broadcast_sd(c + 1), inv = _mm256_broadcast_sd(c + 2);
      l0 = _mm256_max_pd(_mm256_mul_pd(rest(base, step, k0), inv), l0);
      l1 = _mm256_max_pd(_mm256_mul_pd(rest(base, step, k1), inv), l1);
    }
    for (const double* c = upright; c != wall; c += 3) {
      const __m256d base = _mm256_broadcast_sd(c), step = _mm256_broadcast_sd(c + 1);
      l0 = _mm256_blendv_pd(l0, infinity, _mm256_cmp_pd(rest(base, step, k0), zero, _CMP_LT_OQ));
      l1 = _mm256_blendv_pd(l1, infinity, _mm256_cmp_pd(rest(base, step, k1), zero, _CMP_LT_OQ));
    }
    if constexpr (kWiden) {
      const __m256d covered0 = _mm256_cmp_pd(l0, h0, _CMP_LT_OQ), covered1 = _mm256_cmp_pd(l1, h1, _CMP_LT_OQ);
      l0 = _mm256_blendv_pd(a0, _mm256_min_pd(l0, a0), covered0);
      h0 = _mm256_blendv_pd(b0, _mm256_max_pd(h0, b0), covered0);
      l1 = _mm256_blendv_pd(a1, _mm256_min_pd(l1, a1), covered1);
      h1 = _mm256_blendv_pd(b1, _mm256_max_pd(h1, b1), covered1);
    }
    _mm256_maskstore_pd(a + i, in0, l0);
    _mm256_maskstore_pd(b + i, in0, h0);
    if (second) {
      _mm256_maskstore_pd(a + i + 4, in1, l1);
      _mm256_maskstore_pd(b + i + 4, in1, h1);
    }
    k0 = _mm256_add_pd(k0, eight), k1 = _mm256_add_pd(k1, eight);
  }
}

#endif

/// One face along the row, two points at a time where SSE2 is there.
template <Narrow kNarrow>
void narrow_row(double base, double step, double inv, int n, double* __restrict lo, double* __restrict hi) {
#if defined(__SSE2__)
  narrow_sse2<kNarrow>(base, step, inv, n, lo, hi);
#else
  narrow_scalar<kNarrow>(base, step, inv, 0, n, lo, hi);
#endif
}

}  // namespace

void chord_row(const WorldPlanes& p, double x0, double dx, int n, double y, double* __restrict lo,
               double* __restrict hi) {
#if defined(SHORE_CHORDS_AVX)
  if (cpu_has_avx()) return chord_row_avx<false>(p, x0, dx, n, y, lo, hi);
#endif
  for (std::size_t f = 0; f < p.n.size(); ++f) {
    const Vec3 nf = p.n[f];
    const double base = p.d[f] - nf.y * y - nf.x * x0, step = -nf.x * dx;  // rest(k) = base + k step: n_z z <= rest
    if (std::abs(nf.z) < 1e-12)
      narrow_row<Narrow::upright>(base, step, 0.0, n, lo, hi);
    else if (nf.z > 0.0)
      narrow_row<Narrow::upper>(base, step, 1.0 / nf.z, n, lo, hi);
    else
      narrow_row<Narrow::lower>(base, step, 1.0 / nf.z, n, lo, hi);
  }
}

void widen_by_chords(const WorldPlanes& p, double x0, double dx, int n, double y, double* __restrict lower,
                     double* __restrict upper) {
#if defined(SHORE_CHORDS_AVX)
  if (cpu_has_avx()) return chord_row_avx<true>(p, x0, dx, n, y, lower, upper);
#endif
  std::vector<double>& t = p.row_terms;  // the chords, then merged
  t.assign(2 * std::size_t(n), std::numeric_limits<double>::infinity());
  double *lo = t.data(), *hi = lo + n;
  for (int k = 0; k < n; ++k) lo[k] = -std::numeric_limits<double>::infinity();
  chord_row(p, x0, dx, n, y, lo, hi);
  for (int k = 0; k < n; ++k)
    if (lo[k] < hi[k]) {
      lower[k] = std::min(lower[k], lo[k]);
      upper[k] = std::max(upper[k], hi[k]);
    }
}

}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
