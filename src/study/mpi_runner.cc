#include "study/mpi_runner.h"

#include <cstdio>
#include <cstdlib>
#include <deque>
#include <stdexcept>
#include <string>

#ifdef CAMDYN_WITH_MPI
#include <mpi.h>
#endif

namespace camdyn::mpi {

namespace {

// The number of processes an MPI launcher started (0: not started by one).
[[maybe_unused]] int launcher_world_size() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(variable)) return std::atoi(value);
  return std::getenv("PMIX_RANK") != nullptr ? 1 : 0;
}

[[maybe_unused]] bool launched_by_mpi() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(variable) != nullptr) return true;
  return false;
}

#ifdef CAMDYN_WITH_MPI
constexpr int kResultTag = 7;
bool g_initialised = false;  // by Session

void check(int rc, const char* call) {
  if (rc != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(rc, text, &length);
    throw std::runtime_error(std::string(call) + " failed: " + std::string(text, static_cast<std::size_t>(length)));
  }
}
#endif

}  // namespace

#ifdef CAMDYN_WITH_MPI

Session::Session(int* argc, char*** argv) {
  if (!launched_by_mpi()) return;
  check(MPI_Init(argc, argv), "MPI_Init");
  g_initialised = true;
}

Session::~Session() {
  if (!g_initialised) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

bool built_with_mpi() { return true; }

int rank() {
  if (!g_initialised) return 0;
  int r = 0;
  check(MPI_Comm_rank(MPI_COMM_WORLD, &r), "MPI_Comm_rank");
  return r;
}

int size() {
  if (!g_initialised) return 1;
  int n = 1;
  check(MPI_Comm_size(MPI_COMM_WORLD, &n), "MPI_Comm_size");
  return n;
}

void abort_all(int code) {
  if (g_initialised) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

std::string broadcast(const std::string& text) {
  if (size() == 1) return text;
  unsigned long long length = text.size();
  check(MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD), "MPI_Bcast");
  std::string out = rank() == 0 ? text : std::string(static_cast<std::size_t>(length), '\0');
  if (length > 0) check(MPI_Bcast(out.data(), static_cast<int>(length), MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast");
  return out;
}

void distribute_runs(const std::vector<std::size_t>& indices, const std::function<std::string(std::size_t)>& run,
                     const std::function<void(const std::string&)>& on_result) {
  const std::size_t me = static_cast<std::size_t>(rank()), ranks = static_cast<std::size_t>(size());
  if (me != 0) {
    // Non-blocking sends, so a rank never waits for rank 0 to finish its own run.
    std::deque<std::string> buffers;
    std::vector<MPI_Request> requests;
    for (std::size_t k = me; k < indices.size(); k += ranks) {
      buffers.push_back(run(indices[k]));
      requests.emplace_back();
      check(MPI_Isend(buffers.back().data(), static_cast<int>(buffers.back().size()), MPI_CHAR, 0, kResultTag,
                      MPI_COMM_WORLD, &requests.back()),
            "MPI_Isend");
      int all_done = 0;  // lets the MPI library progress the sends
      check(MPI_Testall(static_cast<int>(requests.size()), requests.data(), &all_done, MPI_STATUSES_IGNORE),
            "MPI_Testall");
    }
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    return;
  }
  std::size_t expected = 0;  // results still to come from the other ranks
  for (std::size_t k = 0; k < indices.size(); ++k)
    if (k % ranks != 0) ++expected;
  auto receive = [&](bool block) {
    MPI_Status status;
    int arrived = 1;
    if (block)
      check(MPI_Probe(MPI_ANY_SOURCE, kResultTag, MPI_COMM_WORLD, &status), "MPI_Probe");
    else
      check(MPI_Iprobe(MPI_ANY_SOURCE, kResultTag, MPI_COMM_WORLD, &arrived, &status), "MPI_Iprobe");
    if (!arrived) return false;
    int count = 0;
    check(MPI_Get_count(&status, MPI_CHAR, &count), "MPI_Get_count");
    std::string text(static_cast<std::size_t>(count), '\0');
    check(MPI_Recv(text.data(), count, MPI_CHAR, status.MPI_SOURCE, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
          "MPI_Recv");
    --expected;
    on_result(text);
    return true;
  };
  for (std::size_t k = 0; k < indices.size(); k += ranks) {
    on_result(run(indices[k]));
    while (expected > 0 && receive(false)) {
    }
  }
  while (expected > 0) receive(true);
}

#else  // without MPI: one rank

Session::Session(int* /*argc*/, char*** /*argv*/) {
  // Every rank would run the whole study and write the same files.
  if (launcher_world_size() > 1) {
    std::fprintf(stderr,
                 "camdyn: error: started by an MPI launcher, but this camdyn was built without MPI "
                 "(configure with -DCAMDYN_WITH_MPI=ON); run it without mpirun and use --jobs instead\n");
    std::exit(2);
  }
}
Session::~Session() = default;
bool built_with_mpi() { return false; }
int rank() { return 0; }
int size() { return 1; }
void abort_all(int code) { std::exit(code); }
std::string broadcast(const std::string& text) { return text; }
void distribute_runs(const std::vector<std::size_t>& indices, const std::function<std::string(std::size_t)>& run,
                     const std::function<void(const std::string&)>& on_result) {
  for (const std::size_t i : indices) on_result(run(i));
}

#endif

}  // namespace camdyn::mpi
