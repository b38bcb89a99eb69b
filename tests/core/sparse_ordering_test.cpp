// The sparse step's factor ordering (lib/src/sparse_ordering.hpp): the
// elimination tree against the pattern of Eigen's own factor, the level sort
// against the fill of the order it sorts (Liu's equivalent orderings), and the
// chain the triangular solves wait on for a path, a beam and a grid.
#include "sparse_ordering.hpp"

#include <gtest/gtest.h>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <iostream>
#include <numeric>
#include <vector>

namespace podid {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

Sparse FromTriplets(int n, const std::vector<Eigen::Triplet<double>>& t) {
  Sparse a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  return a;
}

// A chain of n unit springs, grounded at both ends: tridiagonal, SPD.
Sparse Path(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  return FromTriplets(n, t);
}

// The pattern of a beam of Euler-Bernoulli elements (w and theta at each of
// `nodes` nodes, each element coupling the four dofs of its two nodes), with
// a dominant diagonal so that it is SPD.
Sparse BeamPattern(int nodes) {
  std::vector<Eigen::Triplet<double>> t;
  const int n = 2 * nodes;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, 16.0);
  for (int e = 0; e + 1 < nodes; ++e)
    for (int i = 2 * e; i < 2 * e + 4; ++i)
      for (int j = 2 * e; j < 2 * e + 4; ++j)
        if (i != j) t.emplace_back(i, j, -1.0);
  return FromTriplets(n, t);
}

// The 5-point Laplacian of a side x side grid.
Sparse Grid(int side) {
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < side; ++r) {
    for (int c = 0; c < side; ++c) {
      const int i = r * side + c;
      t.emplace_back(i, i, 4.0);
      if (c + 1 < side) {
        t.emplace_back(i, i + 1, -1.0);
        t.emplace_back(i + 1, i, -1.0);
      }
      if (r + 1 < side) {
        t.emplace_back(i, i + side, -1.0);
        t.emplace_back(i + side, i, -1.0);
      }
    }
  }
  return FromTriplets(side * side, t);
}

// a(order, order).
Sparse Permuted(const Sparse& a, const std::vector<int>& order) {
  const int n = static_cast<int>(order.size());
  std::vector<int> position(n);
  for (int k = 0; k < n; ++k) position[order[k]] = k;
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < a.outerSize(); ++j)
    for (Sparse::InnerIterator it(a, j); it; ++it)
      t.emplace_back(position[it.row()], position[j], it.value());
  return FromTriplets(n, t);
}

// L of a(order, order) = L D L^T by Eigen, no further permutation.
Sparse Factor(const Sparse& a, const std::vector<int>& order) {
  const Eigen::SimplicialLDLT<Sparse, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt(
      Permuted(a, order));
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  return ldlt.matrixL().nestedExpression().triangularView<Eigen::StrictlyLower>();
}

bool IsPermutation(std::vector<int> order, int n) {
  std::sort(order.begin(), order.end());
  std::vector<int> identity(n);
  std::iota(identity.begin(), identity.end(), 0);
  return order == identity;
}

std::vector<int> Natural(int n) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  return order;
}

std::vector<int> Amd(const Sparse& a) {
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p;
  Eigen::AMDOrdering<int>()(a, p);
  return std::vector<int>(p.indices().data(), p.indices().data() + p.size());
}

TEST(SparseOrdering, EliminationTreeIsTheFirstSubdiagonalEntryOfEachColumnOfL) {
  // The parent of column j in the elimination tree is the first row below
  // the diagonal where L has an entry (structural, as Eigen stores it).
  const Sparse grid = Grid(9);
  for (const std::vector<int>& order : {Natural(81), Amd(grid)}) {
    const Sparse l = Factor(grid, order);
    const std::vector<int> parent = internal::EliminationTree(grid, order);
    for (int j = 0; j < l.outerSize(); ++j) {
      int first = -1;
      for (Sparse::InnerIterator it(l, j); it; ++it)
        if (it.row() > j && (first == -1 || it.row() < first)) first = static_cast<int>(it.row());
      EXPECT_EQ(parent[j], first) << "column " << j;
    }
  }
}

TEST(SparseOrdering, LevelSortKeepsTheFillAndListsChildrenFirst) {
  // Any order that lists the elimination tree's children before their parent
  // has the same factor nonzeros (Liu 1990): the level sort adds no fill.
  const Sparse grid = Grid(12), beam = BeamPattern(60);
  std::vector<int> reversed = Natural(144);
  std::reverse(reversed.begin(), reversed.end());
  for (const auto& [a, order] : std::vector<std::pair<Sparse, std::vector<int>>>{
           {grid, Natural(144)}, {grid, reversed}, {grid, Amd(grid)}, {beam, Amd(beam)}}) {
    const internal::SparseOrdering sorted = internal::LevelSorted(a, order);
    ASSERT_TRUE(IsPermutation(sorted.order, static_cast<int>(a.cols())));
    EXPECT_EQ(Factor(a, sorted.order).nonZeros(), Factor(a, order).nonZeros());
    const std::vector<int> parent = internal::EliminationTree(a, sorted.order);
    for (int k = 0; k < static_cast<int>(parent.size()); ++k) {
      if (parent[k] != -1) {
        EXPECT_GT(parent[k], k);
      }
    }
  }
}

TEST(SparseOrdering, NestedDissectionShortensTheSolvesChain) {
  // A fill-reducing order alone leaves a path or a beam one chain: AMD's
  // elimination tree is a quarter as high as the matrix is long or more (999
  // levels for the 1000-node path). The chain-breaking order cuts it to a
  // small fraction (kMaxHeightFraction: at most 1/8, so that independent rows
  // are always within the processor's out-of-order window; measured 12, 20
  // and 85 levels) for at most kMaxFillRatio times AMD's fill: nested
  // dissection couples each node of a path to the separators on both of its
  // sides, two entries per row of L where AMD has one (measured 1.98 for the
  // path, 1.75 for the beam, 1.08 for the grid).
  constexpr double kMaxHeightFraction = 1.0 / 8.0;
  constexpr double kMaxFillRatio = 2.5;
  for (const Sparse& a : {Path(1000), BeamPattern(300), Grid(30)}) {
    const int n = static_cast<int>(a.cols());
    const internal::SparseOrdering ordering = internal::ChainBreakingOrdering(a);
    ASSERT_TRUE(IsPermutation(ordering.order, n));
    EXPECT_EQ(ordering.method, "METIS nested dissection");
    const internal::SparseOrdering amd = internal::LevelSorted(a, Amd(a));
    const auto fill = Factor(a, ordering.order).nonZeros(),
               amd_fill = Factor(a, amd.order).nonZeros();
    std::cout << n << " rows: height " << ordering.tree_height << " (AMD " << amd.tree_height
              << "), L " << fill << " nonzeros (AMD " << amd_fill << ")\n";
    EXPECT_LE(ordering.tree_height, kMaxHeightFraction * n);
    EXPECT_LE(static_cast<double>(fill), kMaxFillRatio * static_cast<double>(amd_fill));
    if (a.cols() == 1000) {
      EXPECT_GE(amd.tree_height, n / 4);
    }
  }
}

TEST(SparseOrdering, DiagonalAndEmptyMatrices) {
  // No off-diagonal entries: nothing to fill, no chain; METIS is not called.
  Sparse diagonal(5, 5);
  diagonal.setIdentity();
  const internal::SparseOrdering ordering = internal::ChainBreakingOrdering(diagonal);
  EXPECT_EQ(ordering.order, Natural(5));
  EXPECT_EQ(ordering.tree_height, 1);
  EXPECT_EQ(ordering.method, "natural (no off-diagonal entries)");
  const internal::SparseOrdering empty = internal::ChainBreakingOrdering(Sparse(0, 0));
  EXPECT_TRUE(empty.order.empty());
  EXPECT_EQ(empty.tree_height, 0);
}

}  // namespace
}  // namespace podid
