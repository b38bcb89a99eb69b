#include "sparse_ordering.hpp"

#include <metis.h>

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <mutex>
#include <numeric>

namespace podid::internal {
namespace {

// METIS_NodeND swaps the process's SIGABRT and SIGTERM handlers for its own
// while it runs (GKlib's out-of-memory recovery) and restores them on return;
// two threads interleaving that would leave METIS's handler installed. Orders
// are computed once per integrator, so one at a time costs nothing.
std::mutex metis_mutex;

// METIS's nested dissection of the graph of `a` (diagonal left out), or the
// natural order when the graph has no edges (nothing to fill, no chain); with
// *method saying which. False with the reason in *method if METIS fails.
bool NestedDissection(const Eigen::SparseMatrix<double>& a,
                      std::vector<int>* order,
                      std::string* method) {
  const int n = static_cast<int>(a.cols());
  std::vector<idx_t> xadj(static_cast<std::size_t>(n) + 1, 0), adjncy;
  adjncy.reserve(static_cast<std::size_t>(a.nonZeros()));
  for (int j = 0; j < n; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it)
      if (it.row() != j) adjncy.push_back(static_cast<idx_t>(it.row()));
    xadj[static_cast<std::size_t>(j) + 1] = static_cast<idx_t>(adjncy.size());
  }
  if (adjncy.empty()) {
    order->resize(static_cast<std::size_t>(n));
    std::iota(order->begin(), order->end(), 0);
    *method = "natural (no off-diagonal entries)";
    return true;
  }
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  idx_t nvtxs = n;
  std::vector<idx_t> perm(static_cast<std::size_t>(n)), iperm(static_cast<std::size_t>(n));
  int status = 0;
  {
    const std::lock_guard<std::mutex> lock(metis_mutex);
    status = METIS_NodeND(&nvtxs, xadj.data(), adjncy.data(), nullptr, options, perm.data(),
                          iperm.data());
  }
  if (status != METIS_OK) {
    *method = "METIS_NodeND returned " + std::to_string(status);
    return false;
  }
  // METIS: row k of the permuted matrix is row perm[k] of `a`.
  order->assign(perm.begin(), perm.end());
  *method = "METIS nested dissection";
  return true;
}

}  // namespace

std::vector<int> EliminationTree(const Eigen::SparseMatrix<double>& a,
                                 const std::vector<int>& order) {
  // Liu's algorithm with path compression over the upper triangle of
  // a(order, order), read column by column from `a`'s columns.
  const int n = static_cast<int>(order.size());
  std::vector<int> position(static_cast<std::size_t>(n)), parent(static_cast<std::size_t>(n), -1),
      ancestor(static_cast<std::size_t>(n), -1);
  for (int k = 0; k < n; ++k) position[order[k]] = k;
  for (int k = 0; k < n; ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, order[k]); it; ++it) {
      int i = position[it.row()];
      while (i != -1 && i < k) {
        const int next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
        i = next;
      }
    }
  }
  return parent;
}

SparseOrdering LevelSorted(const Eigen::SparseMatrix<double>& a, std::vector<int> order) {
  SparseOrdering result;
  const int n = static_cast<int>(order.size());
  // Height of each node above the leaves; children precede their parent.
  const std::vector<int> parent = EliminationTree(a, order);
  std::vector<int> level(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    if (parent[k] != -1) level[parent[k]] = std::max(level[parent[k]], level[k] + 1);
    result.tree_height = std::max(result.tree_height, level[k] + 1);
  }
  std::vector<int> by_level(static_cast<std::size_t>(n));
  std::iota(by_level.begin(), by_level.end(), 0);
  std::stable_sort(by_level.begin(), by_level.end(),
                   [&](int x, int y) { return level[x] < level[y]; });
  result.order.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) result.order[k] = order[by_level[k]];
  return result;
}

SparseOrdering ChainBreakingOrdering(const Eigen::SparseMatrix<double>& a) {
  const int n = static_cast<int>(a.cols());
  std::vector<int> order;
  std::string method;
  if (!NestedDissection(a, &order, &method)) {
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p;
    Eigen::AMDOrdering<int>()(a, p);
    // Eigen's ordering permutation maps a new position to the old row.
    order.assign(p.indices().data(), p.indices().data() + n);
    method = "AMD (" + method + ")";
  }
  SparseOrdering result = LevelSorted(a, std::move(order));
  result.method = std::move(method);
  return result;
}

}  // namespace podid::internal
