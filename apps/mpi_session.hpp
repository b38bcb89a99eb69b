#pragma once
// MPI for the CLI (issue 14): when podid is built with MPI and started by
// mpirun or srun, `landscape` spreads its grid points and `identify
// --multistart` its starts over the ranks; rank 0 writes every output. Started
// any other way (or built without MPI) the same binary runs as one process:
// Size() == 1 and every collective below is the identity.
//
// Collectives must be called by every rank in the same order. A rank that
// fails passes its message to CheckAll() at the next collective point, so that
// no rank waits forever on one that left; every rank then reports the failure.

#include <cstdint>
#include <exception>
#include <string>

namespace podid::cli::mpi {

/// Initialises MPI (funneled threading: OpenMP inside a rank is fine) for the
/// lifetime of the object when the environment shows an MPI launcher
/// (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK); otherwise does nothing.
class Session {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

 private:
  bool initialised_ = false;
};

/// True when MPI was initialised and there is more than one rank.
bool Active();
int Rank();  ///< 0 without MPI
int Size();  ///< 1 without MPI
/// Ranks on this machine (MPI_COMM_TYPE_SHARED); 1 without MPI.
int LocalSize();
/// Threads for a rank when the user gave 0: the cores OpenMP sees shared by
/// the ranks on this machine (at least 1), so N ranks do not run N x cores threads.
/// Throws std::invalid_argument if OpenMP's count exceeds ident::kMaxThreads.
int DefaultThreads();

/// Collective. `local_error` is empty when this rank succeeded. Returns ""
/// when every rank succeeded, else the lowest failed rank's message as
/// "rank k of n: ..." (the same text on every rank).
std::string CheckAll(const std::string& local_error);

/// Collective: runs `work` on this rank; an exception it throws becomes this
/// rank's message to CheckAll(). Returns CheckAll's result: "" when every
/// rank succeeded. Without several ranks the exception propagates as usual.
template <typename Work>
std::string RunCollectively(Work&& work) {
  std::string error;
  try {
    work();
  } catch (const std::exception& e) {  // e.g. out of memory on one rank
    if (!Active()) throw;
    error = e.what();
  }
  return CheckAll(error);
}

/// Collective: element-wise sum over the ranks, the result on every rank.
/// Used to merge disjoint shares: a rank leaves entries it does not own at
/// exactly 0, so the sum is the owner's value bit for bit (x + 0 == x, NaN
/// included).
void SumOnAll(double* values, std::int64_t count);
void SumOnAll(std::int64_t* values, std::int64_t count);

/// Collective: the value of rank `root` on every rank.
void Broadcast(std::string* text, int root);

}  // namespace podid::cli::mpi
