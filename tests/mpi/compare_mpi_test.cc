// A compare study under `mpirun -np 2` writes the same comparison.csv as the
// threaded run (timing column aside), and only rank 0 writes outputs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"

namespace {

namespace fs = std::filesystem;
using camdyn::test::read_text;
using camdyn::test::without_last_column;

TEST(CompareMpi, TwoRanksWriteTheSameTableAsThreads) {
  const fs::path dir = fs::temp_directory_path() / ("camdyn_compare_mpi_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path study = dir / "study.json";
  std::ofstream(study) << R"({
    "extends": ")" << CAMDYN_SOURCE_DIR
                       << R"(/studies/quickstart.json",
    "name": "mpi", "study": "compare",
    "simulation": { "cycles": 2, "discard_cycles": 1, "output_step_deg": 1.0 },
    "cases": [ { "name": "cycloidal" }, { "name": "soft", "set": ["mechanism.contact.stiffness=1e4"] },
               { "name": "heavy", "set": ["mechanism.follower.mass=0.45"] } ],
    "grid": { "mechanism.cam.rpm": [900, 1100, 1300, 1500] },
    "overlays": [ { "mechanism.cam.rpm": 1300 } ]
  })";
  // OpenMPI refuses root unless told, and 2 ranks may exceed the slots of a small machine.
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
  ASSERT_EQ(camdyn::test::run_camdyn({"run", study.string(), "--jobs", "2", "--out", (dir / "threads").string()}, dir,
                                     "threads")
                .code,
            0);
  const camdyn::test::Outcome mpi = camdyn::test::run_process(
      {CAMDYN_MPIEXEC, "-np", "2", CAMDYN_BINARY, "run", study.string(), "--out", (dir / "mpi").string()}, dir, "mpi");
  ASSERT_EQ(mpi.code, 0) << mpi.err;
  const std::string threads = without_last_column(dir / "threads" / "comparison.csv");
  EXPECT_EQ(std::count(threads.begin(), threads.end(), '\n'), 13);
  EXPECT_NE(threads.find(",failed,"), std::string::npos);  // the soft case fails: failures travel too
  EXPECT_EQ(without_last_column(dir / "mpi" / "comparison.csv"), threads);
  EXPECT_NE(read_text(dir / "mpi" / "report.html").find("MPI ranks"), std::string::npos);
  // One summary (rank 0's), and the journal has every run once.
  const std::string& out = mpi.out;
  EXPECT_EQ(out.find("mpi: 12 runs"), out.rfind("mpi: 12 runs"));
  const std::string journal = read_text(dir / "mpi" / "journal.jsonl");
  EXPECT_EQ(std::count(journal.begin(), journal.end(), '\n'), 13);
  fs::remove_all(dir);
}

}  // namespace
