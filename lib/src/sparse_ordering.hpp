// The elimination order of the sparse condensed step's factor S_bb = L D L^T
// (newmark.cpp). A fill-reducing order alone (AMD) turns a beam or a chain into
// one path: every row of the triangular solves waits for the row before it,
// and the step runs at the latency of that chain. Nested dissection cuts the
// structure into independent pieces, and listing the elimination tree level
// by level puts rows that do not depend on each other next to each other, so
// the processor overlaps them. Any order that lists children before parents
// gives the same factor nonzeros (Liu 1990), so the second step costs no fill.
#pragma once

#include <Eigen/SparseCore>
#include <string>
#include <vector>

namespace podid::internal {

struct SparseOrdering {
  std::vector<int> order;  ///< order[k] = the row (and column) of `a` eliminated k-th
  int tree_height = 0;     ///< levels of the elimination tree: the solves' dependency chain
  std::string method;      ///< how the fill-reducing part was found (and why METIS was not used)
};

/// `a`: square with a symmetric pattern (both triangles stored). The order is
/// deterministic (METIS with its fixed default seed).
SparseOrdering ChainBreakingOrdering(const Eigen::SparseMatrix<double>& a);

/// `order` listed by the levels of its elimination tree (leaves first, stable
/// within a level), with the tree's height; `method` left empty.
SparseOrdering LevelSorted(const Eigen::SparseMatrix<double>& a, std::vector<int> order);

/// The elimination tree of a(order, order) (parent[k] = -1 at a root), from
/// the pattern only.
std::vector<int> EliminationTree(const Eigen::SparseMatrix<double>& a,
                                 const std::vector<int>& order);

}  // namespace podid::internal
