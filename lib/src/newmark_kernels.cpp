#include "newmark_kernels.hpp"

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define PODID_NEWMARK_AVX2 1
#endif

namespace podid::internal {
namespace {

// out = A u: blocks of 8, 4, 2, 1 rows, each accumulated in registers over all
// columns (fixed-size Eigen vectors, so SIMD without relying on the
// auto-vectoriser). Eigen's general GEMV pays more in set-up and blocking than
// it saves here.
template <int R>
void MultiplyRows(const double* a, int lda, int cols, const double* u, double* out) {
  using Block = Eigen::Matrix<double, R, 1>;
  Block acc = Eigen::Map<const Block>(a) * u[0];
  for (int j = 1; j < cols; ++j) acc.noalias() += Eigen::Map<const Block>(a + j * lda) * u[j];
  Eigen::Map<Block> result(out);
  result = acc;
}

void MultiplySmall(const double* a, int rows, int cols, const double* u, double* out) {
  int i = 0;
  for (; i + 8 <= rows; i += 8) MultiplyRows<8>(a + i, rows, cols, u, out + i);
  if (i + 4 <= rows) {
    MultiplyRows<4>(a + i, rows, cols, u, out + i);
    i += 4;
  }
  if (i + 2 <= rows) {
    MultiplyRows<2>(a + i, rows, cols, u, out + i);
    i += 2;
  }
  if (i < rows) MultiplyRows<1>(a + i, rows, cols, u, out + i);
}

// The update of newmark_kernels.hpp for dofs [begin, n), one at a time.
inline void UpdateRange(const NewmarkCoefficients& c, int begin, int n, const double* __restrict x_new,
                        double* __restrict z, double* __restrict u) {
  const double a0 = c.a0, a1 = c.a1, a2 = c.a2, a3 = c.a3, a4 = c.a4, a5 = c.a5;
  const double dt = c.step_s, g = c.gamma, one_minus_g = 1.0 - c.gamma;
  double* __restrict zv = z + n;
  double* __restrict za = z + 2 * n;
  for (int i = begin; i < n; ++i) {
    const double xn = x_new[i];
    const double an = a0 * (xn - z[i]) - a2 * zv[i] - a3 * za[i];
    const double vn = zv[i] + dt * (one_minus_g * za[i] + g * an);
    u[i] = a0 * xn + a2 * vn + a3 * an;
    u[n + i] = a1 * xn + a4 * vn + a5 * an;
    z[i] = xn;
    zv[i] = vn;
    za[i] = an;
  }
}

bool UpdatePortable(const NewmarkCoefficients& c, int n, const double* y, const double* h, double x_a,
                    double* x_new, double* z, double* u) {
  bool bounded = true;
  if (h != nullptr) {
    for (int i = 0; i < n; ++i) {
      x_new[i] = y[i] - h[i] * x_a;
      bounded &= std::abs(x_new[i]) <= c.max_displacement;  // NaN fails too
    }
  } else {
    for (int i = 0; i < n; ++i) bounded &= std::abs(x_new[i]) <= c.max_displacement;
  }
  if (!bounded) return false;
  UpdateRange(c, 0, n, x_new, z, u);
  return true;
}

#ifdef PODID_NEWMARK_AVX2
// The same product with AVX2 + FMA (4 doubles a register, fused multiply-add),
// compiled for that target only and called only when the CPU reports both.
// K registers of 4 rows each (rows i .. i + 4K - 1); each register has two
// accumulators, even and odd columns, summed at the end: the chain of
// dependent FMAs (4 cycles each) is half as long. FMA rounds once where SSE2
// rounds twice and the sum's order differs: round-off only.
template <int K>
__attribute__((target("avx2,fma"))) void MultiplyRowsAvx2(const double* a, int rows, int cols,
                                                          const double* u, double* out) {
  __m256d even[K], odd[K];
  const __m256d b0 = _mm256_broadcast_sd(u);
#pragma GCC unroll 4
  for (int k = 0; k < K; ++k) {
    even[k] = _mm256_mul_pd(_mm256_loadu_pd(a + 4 * k), b0);
    odd[k] = _mm256_setzero_pd();
  }
  int j = 1;
  for (; j + 1 < cols; j += 2) {
    const double* c0 = a + static_cast<std::ptrdiff_t>(j) * rows;
    const double* c1 = c0 + rows;
    const __m256d b_odd = _mm256_broadcast_sd(u + j);
    const __m256d b_even = _mm256_broadcast_sd(u + j + 1);
#pragma GCC unroll 4
    for (int k = 0; k < K; ++k) {
      odd[k] = _mm256_fmadd_pd(_mm256_loadu_pd(c0 + 4 * k), b_odd, odd[k]);
      even[k] = _mm256_fmadd_pd(_mm256_loadu_pd(c1 + 4 * k), b_even, even[k]);
    }
  }
  if (j < cols) {
    const double* c0 = a + static_cast<std::ptrdiff_t>(j) * rows;
    const __m256d b = _mm256_broadcast_sd(u + j);
#pragma GCC unroll 4
    for (int k = 0; k < K; ++k) odd[k] = _mm256_fmadd_pd(_mm256_loadu_pd(c0 + 4 * k), b, odd[k]);
  }
#pragma GCC unroll 4
  for (int k = 0; k < K; ++k) _mm256_storeu_pd(out + 4 * k, _mm256_add_pd(even[k], odd[k]));
}

__attribute__((target("avx2,fma"))) void MultiplySmallAvx2(const double* a, int rows, int cols,
                                                           const double* u, double* out) {
  int i = 0;
  for (; i + 16 <= rows; i += 16) MultiplyRowsAvx2<4>(a + i, rows, cols, u, out + i);
  const int left = (rows - i) / 4;  // 0..3 registers, one pass for all of them
  if (left == 3) MultiplyRowsAvx2<3>(a + i, rows, cols, u, out + i);
  if (left == 2) MultiplyRowsAvx2<2>(a + i, rows, cols, u, out + i);
  if (left == 1) MultiplyRowsAvx2<1>(a + i, rows, cols, u, out + i);
  for (i += 4 * left; i < rows; ++i) {
    double s = a[i] * u[0];
    for (int j = 1; j < cols; ++j) s = std::fma(a[static_cast<std::ptrdiff_t>(j) * rows + i], u[j], s);
    out[i] = s;
  }
}

// The update with AVX2 on 4 dofs at a time (no FMA in its target: the same
// roundings as UpdatePortable, so the same bits).
__attribute__((target("avx2"))) bool UpdateAvx2(const NewmarkCoefficients& c, int n, const double* y,
                                                 const double* h, double x_a, double* x_new, double* z,
                                                 double* u) {
  const int vector_end = n - n % 4;
  const __m256d sign = _mm256_set1_pd(-0.0);
  const __m256d bound = _mm256_set1_pd(c.max_displacement);
  __m256d ok = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  bool bounded = true;
  if (h != nullptr) {
    const __m256d xa = _mm256_set1_pd(x_a);
    for (int i = 0; i < vector_end; i += 4) {
      const __m256d xn = _mm256_sub_pd(_mm256_loadu_pd(y + i), _mm256_mul_pd(_mm256_loadu_pd(h + i), xa));
      _mm256_storeu_pd(x_new + i, xn);
      // |x| <= bound is false for NaN (ordered comparison).
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_andnot_pd(sign, xn), bound, _CMP_LE_OQ));
    }
    for (int i = vector_end; i < n; ++i) {
      x_new[i] = y[i] - h[i] * x_a;
      bounded &= std::abs(x_new[i]) <= c.max_displacement;
    }
  } else {
    for (int i = 0; i < vector_end; i += 4) {
      const __m256d xn = _mm256_loadu_pd(x_new + i);
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_andnot_pd(sign, xn), bound, _CMP_LE_OQ));
    }
    for (int i = vector_end; i < n; ++i) bounded &= std::abs(x_new[i]) <= c.max_displacement;
  }
  if (!bounded || _mm256_movemask_pd(ok) != 0xF) return false;

  const __m256d a0 = _mm256_set1_pd(c.a0), a1 = _mm256_set1_pd(c.a1), a2 = _mm256_set1_pd(c.a2);
  const __m256d a3 = _mm256_set1_pd(c.a3), a4 = _mm256_set1_pd(c.a4), a5 = _mm256_set1_pd(c.a5);
  const __m256d dt = _mm256_set1_pd(c.step_s), g = _mm256_set1_pd(c.gamma);
  const __m256d one_minus_g = _mm256_set1_pd(1.0 - c.gamma);
  double* const zv = z + n;
  double* const za = z + 2 * n;
  for (int i = 0; i < vector_end; i += 4) {
    const __m256d xn = _mm256_loadu_pd(x_new + i);
    const __m256d x = _mm256_loadu_pd(z + i), v = _mm256_loadu_pd(zv + i), acc = _mm256_loadu_pd(za + i);
    // an = a0 (xn - x) - a2 v - a3 acc; vn = v + dt ((1 - g) acc + g an)
    const __m256d an = _mm256_sub_pd(_mm256_sub_pd(_mm256_mul_pd(a0, _mm256_sub_pd(xn, x)), _mm256_mul_pd(a2, v)),
                                     _mm256_mul_pd(a3, acc));
    const __m256d vn = _mm256_add_pd(
        v, _mm256_mul_pd(dt, _mm256_add_pd(_mm256_mul_pd(one_minus_g, acc), _mm256_mul_pd(g, an))));
    _mm256_storeu_pd(u + i, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, xn), _mm256_mul_pd(a2, vn)),
                                          _mm256_mul_pd(a3, an)));
    _mm256_storeu_pd(u + n + i, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a1, xn), _mm256_mul_pd(a4, vn)),
                                              _mm256_mul_pd(a5, an)));
    _mm256_storeu_pd(z + i, xn);
    _mm256_storeu_pd(zv + i, vn);
    _mm256_storeu_pd(za + i, an);
  }
  UpdateRange(c, vector_end, n, x_new, z, u);
  return true;
}

bool CpuHasAvx2Fma() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
#endif

}  // namespace

MultiplyKernel SelectMultiplyKernel(bool cpu_dispatch) {
#ifdef PODID_NEWMARK_AVX2
  if (cpu_dispatch && CpuHasAvx2Fma()) return MultiplySmallAvx2;
#endif
  return MultiplySmall;
}

UpdateKernel SelectUpdateKernel(bool cpu_dispatch) {
#ifdef PODID_NEWMARK_AVX2
  if (cpu_dispatch && CpuHasAvx2Fma()) return UpdateAvx2;
#endif
  return UpdatePortable;
}

}  // namespace podid::internal
