// ResizeWithHugePages (wavelet/src/huge_pages.hpp): the huge-page advice is a
// hint whose effect depends on the kernel's settings, so these tests check
// what must hold either way: the contract of std::vector::resize.
#include "../../wavelet/src/huge_pages.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace podid::wavelet::internal {
namespace {

// Above AdviseHugePages' 8 MiB threshold, so the advised path runs.
constexpr std::size_t kLarge = std::size_t{16} << 20;

TEST(ResizeWithHugePages, GrowingKeepsTheElementsAndZeroesTheNewOnes) {
  std::vector<std::uint8_t> v = {1, 2, 3};
  ResizeWithHugePages(&v, kLarge);
  ASSERT_EQ(v.size(), kLarge);
  EXPECT_EQ(v[0], 1);
  EXPECT_EQ(v[1], 2);
  EXPECT_EQ(v[2], 3);
  EXPECT_TRUE(std::all_of(v.begin() + 3, v.end(), [](std::uint8_t b) { return b == 0; }));
}

TEST(ResizeWithHugePages, RegrowingWithinTheCapacityZeroesAgain) {
  // The ridge programme shrinks and regrows its buffers between records: the
  // regrown elements are new ones (zero), not the old storage's bytes.
  std::vector<std::uint16_t> v;
  ResizeWithHugePages(&v, kLarge / sizeof(std::uint16_t));
  std::fill(v.begin(), v.end(), std::uint16_t{7});
  ResizeWithHugePages(&v, 5);
  ASSERT_EQ(v.size(), 5u);
  EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](std::uint16_t b) { return b == 7; }));
  ResizeWithHugePages(&v, kLarge / sizeof(std::uint16_t));
  EXPECT_TRUE(std::all_of(v.begin(), v.begin() + 5, [](std::uint16_t b) { return b == 7; }));
  EXPECT_TRUE(std::all_of(v.begin() + 5, v.end(), [](std::uint16_t b) { return b == 0; }));
}

TEST(ResizeWithHugePages, SmallAndEmptySizesAreAPlainResize) {
  std::vector<double> v(3, 1.5);
  ResizeWithHugePages(&v, 1000);  // below the threshold: no advice
  ASSERT_EQ(v.size(), 1000u);
  EXPECT_EQ(v[2], 1.5);
  EXPECT_EQ(v[999], 0.0);
  ResizeWithHugePages(&v, 0);
  EXPECT_TRUE(v.empty());
}

}  // namespace
}  // namespace podid::wavelet::internal
