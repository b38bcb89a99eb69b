// The dense condensed path's kernels (lib/src/newmark_kernels.hpp): the AVX2
// update against the portable one, bit for bit, and the bounds check.
#include "newmark_kernels.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace podid {
namespace {

internal::NewmarkCoefficients Coefficients() {
  const double dt = 2e-4, g = 0.5, b = 0.25;
  return {1.0 / (b * dt * dt), g / (b * dt), 1.0 / (b * dt), 1.0 / (2.0 * b) - 1.0, g / b - 1.0,
          dt * (g / (2.0 * b) - 1.0), dt, g, 1e3};
}

struct KernelState {
  std::vector<double> y, h, x_new, z, u;
};

KernelState RandomState(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1e-3, 1e-3);
  KernelState s{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n),
                std::vector<double>(3 * n), std::vector<double>(2 * n, 0.0)};
  for (double* v : {s.y.data(), s.h.data(), s.x_new.data()})
    for (int i = 0; i < n; ++i) v[i] = uniform(rng);
  for (double& v : s.z) v = uniform(rng) * 1e3;
  s.h[0] = 0.0;
  return s;
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(NewmarkKernelsTest, DispatchedUpdateGivesThePortableBits) {
  // Both do the same roundings per dof in the same order (no FMA): the same
  // bits, on sizes with and without a tail after the 4-dof blocks, with
  // x_new computed (h given) and given.
  const internal::UpdateKernel portable = internal::SelectUpdateKernel(false);
  const internal::UpdateKernel dispatched = internal::SelectUpdateKernel(true);
  const internal::NewmarkCoefficients c = Coefficients();
  for (const int n : {1, 4, 7, 12, 14, 20}) {
    for (const bool with_h : {true, false}) {
      SCOPED_TRACE(::testing::Message() << n << " dofs, h " << with_h);
      KernelState a = RandomState(n, 7u + static_cast<unsigned>(n)), b = a;
      const double x_a = 3e-4;
      ASSERT_TRUE(portable(c, n, a.y.data(), with_h ? a.h.data() : nullptr, x_a, a.x_new.data(),
                           a.z.data(), a.u.data()));
      ASSERT_TRUE(dispatched(c, n, b.y.data(), with_h ? b.h.data() : nullptr, x_a, b.x_new.data(),
                             b.z.data(), b.u.data()));
      EXPECT_TRUE(SameBits(a.x_new, b.x_new));
      EXPECT_TRUE(SameBits(a.z, b.z));
      EXPECT_TRUE(SameBits(a.u, b.u));
      // The update itself against its definition, for dof n - 1.
      const int i = n - 1;
      const KernelState before = RandomState(n, 7u + static_cast<unsigned>(n));
      const double xn = with_h ? before.y[i] - before.h[i] * x_a : before.x_new[i];
      const double an = c.a0 * (xn - before.z[i]) - c.a2 * before.z[n + i] - c.a3 * before.z[2 * n + i];
      const double vn = before.z[n + i] + c.step_s * ((1.0 - c.gamma) * before.z[2 * n + i] + c.gamma * an);
      EXPECT_EQ(a.z[i], xn);
      EXPECT_EQ(a.z[n + i], vn);
      EXPECT_EQ(a.z[2 * n + i], an);
      EXPECT_EQ(a.u[i], c.a0 * xn + c.a2 * vn + c.a3 * an);
      EXPECT_EQ(a.u[n + i], c.a1 * xn + c.a4 * vn + c.a5 * an);
    }
  }
}

TEST(NewmarkKernelsTest, UnboundedOrNonFiniteStateIsRefusedAndLeftUntouched) {
  const internal::NewmarkCoefficients c = Coefficients();
  for (const bool cpu_dispatch : {false, true}) {
    const internal::UpdateKernel update = internal::SelectUpdateKernel(cpu_dispatch);
    for (const double bad : {2e3, -2e3, std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity()}) {
      for (const int where : {0, 5, 13}) {  // in a 4-dof block and in the tail
        KernelState s = RandomState(14, 3u);
        s.x_new[where] = bad;
        const KernelState before = s;
        EXPECT_FALSE(update(c, 14, nullptr, nullptr, 0.0, s.x_new.data(), s.z.data(), s.u.data()))
            << "dispatch " << cpu_dispatch << ", value " << bad << " at " << where;
        EXPECT_TRUE(SameBits(s.z, before.z));
        EXPECT_TRUE(SameBits(s.u, before.u));
      }
    }
  }
}

}  // namespace
}  // namespace podid
