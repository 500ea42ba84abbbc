// Spreading the runs of a study over MPI ranks (`mpirun -np N camdyn run
// study.json`), when camdyn is built with -DCAMDYN_WITH_MPI=ON. MPI is only
// initialised when an MPI launcher started the process (mpirun sets
// OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK); otherwise, and in a build
// without MPI, everything here acts as a single rank 0 of 1.
//
// Distribution is static round robin: the k-th pending run goes to rank
// k mod N; every rank does one run at a time and sends each result (a text:
// a journal record) to rank 0, which journals them as they arrive and alone
// writes the outputs.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace camdyn::mpi {

/// Initialises MPI (if built with it and started by an MPI launcher) for the
/// lifetime of the object; finalises it on destruction. One per process, in main.
class Session {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

/// Whether camdyn was built with MPI support.
bool built_with_mpi();
/// This process's rank (0 without MPI) and the number of ranks (1 without MPI).
int rank();
int size();

/// Ends every rank with `code` (MPI_Abort); without MPI, std::exit(code).
[[noreturn]] void abort_all(int code);

/// Rank 0's `text`, on every rank (collective: every rank must call it).
std::string broadcast(const std::string& text);

/// Runs `run(indices[k])` on rank k mod size(), one at a time per rank; each
/// result reaches `on_result` on rank 0, in the order results arrive (rank 0's
/// own after each of its runs, the others' between and after them).
/// Collective. On ranks other than 0 `on_result` is never called. Throws
/// std::runtime_error if an MPI call fails.
void distribute_runs(const std::vector<std::size_t>& indices, const std::function<std::string(std::size_t)>& run,
                     const std::function<void(const std::string&)>& on_result);

}  // namespace camdyn::mpi
