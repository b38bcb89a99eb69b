#include "mpi_session.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/ident/landscape.hpp"

#ifdef PODID_HAVE_MPI
#include <mpi.h>
#endif

namespace podid::cli::mpi {
namespace {

bool g_active = false;
int g_rank = 0;
int g_size = 1;
int g_local_size = 1;

bool LaunchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

#ifdef PODID_HAVE_MPI
// MPI counts are int: send large arrays in chunks.
constexpr std::int64_t kChunk = std::numeric_limits<int>::max() / 2;
#endif

}  // namespace

Session::Session([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
#ifdef PODID_HAVE_MPI
  if (!LaunchedByMpi()) return;
  int provided = 0;
  // MPI's default error handler aborts the job if this fails.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_active = g_size > 1;
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, g_rank, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &g_local_size);
  MPI_Comm_free(&node);
  if (!g_active) {  // one rank: behave exactly as without MPI
    g_rank = 0;
  }
  initialised_ = true;
#else
  (void)LaunchedByMpi;
#endif
}

Session::~Session() {
#ifdef PODID_HAVE_MPI
  if (initialised_) MPI_Finalize();
#endif
}

bool Active() { return g_active; }
int Rank() { return g_rank; }
int Size() { return g_size; }
int LocalSize() { return g_local_size; }
int DefaultThreads() {
  // OpenMP's count comes from OMP_NUM_THREADS (else the cores): it gets
  // --threads' bound, named as what the user set.
  const int available = omp_get_max_threads();
  if (available > ident::kMaxThreads) {
    const char* env = std::getenv("OMP_NUM_THREADS");
    ThrowInvalid("--threads 0",
                 "OpenMP's thread count (OMP_NUM_THREADS, else the cores) of at most " +
                     ToText(ident::kMaxThreads),
                 env != nullptr ? "OMP_NUM_THREADS=" + std::string(env) : ToText(available));
  }
  return std::max(1, available / g_local_size);
}

std::string CheckAll(const std::string& local_error) {
  if (!g_active) return local_error;
#ifdef PODID_HAVE_MPI
  int mine = local_error.empty() ? g_size : g_rank;
  int first = g_size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == g_size) return {};
  std::string message = local_error;
  Broadcast(&message, first);
  return "rank " + std::to_string(first) + " of " + std::to_string(g_size) + ": " + message;
#else
  return local_error;
#endif
}

#ifdef PODID_HAVE_MPI
namespace {
// MPI counts are int: large arrays go in chunks.
template <typename T>
void SumChunks(T* values, std::int64_t count, MPI_Datatype type) {
  if (!g_active) return;
  for (std::int64_t offset = 0; offset < count; offset += kChunk) {
    const int n = static_cast<int>(std::min(kChunk, count - offset));
    MPI_Allreduce(MPI_IN_PLACE, values + offset, n, type, MPI_SUM, MPI_COMM_WORLD);
  }
}
}  // namespace
#endif

void SumOnAll([[maybe_unused]] double* values, [[maybe_unused]] std::int64_t count) {
#ifdef PODID_HAVE_MPI
  SumChunks(values, count, MPI_DOUBLE);
#endif
}

void SumOnAll([[maybe_unused]] std::int64_t* values, [[maybe_unused]] std::int64_t count) {
#ifdef PODID_HAVE_MPI
  SumChunks(values, count, MPI_INT64_T);
#endif
}

void Broadcast([[maybe_unused]] std::string* text, [[maybe_unused]] int root) {
#ifdef PODID_HAVE_MPI
  if (!g_active) return;
  long long size = g_rank == root ? static_cast<long long>(text->size()) : 0;
  MPI_Bcast(&size, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD);
  text->resize(static_cast<std::size_t>(size));
  for (long long offset = 0; offset < size; offset += kChunk) {
    const int n = static_cast<int>(std::min<long long>(kChunk, size - offset));
    MPI_Bcast(text->data() + offset, n, MPI_CHAR, root, MPI_COMM_WORLD);
  }
#endif
}

}  // namespace podid::cli::mpi
