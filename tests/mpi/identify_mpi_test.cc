// The starts of an identify study spread over `mpirun -np 3` (start k on
// rank k; optim/identify/identify.h IdentifyOptions::over_ranks) give the
// single process's fit to the bit: every start's values and cost, the
// identified parameters, the final cost and the simulation count. The best
// start is the third, which rank 2 ran: rank 0 fits it again to write its fit.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_run.h"
#include "io/config.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

/// identified.json of the drop-rig stiffness fit (tests/data/identify/single.json)
/// from three starts, run by `launcher` in front of camdyn (none: one process).
Json fit_three_starts(const fs::path& dir, const std::string& tag, const std::vector<std::string>& launcher) {
  std::vector<std::string> argv = launcher;
  for (const std::string& a :
       {std::string(CAMDYN_BINARY), std::string("run"), std::string(CAMDYN_TEST_DATA_DIR) + "/identify/single.json",
        std::string("--jobs"), std::string("1"), std::string("--set"), std::string("solver.starts=3"),
        std::string("--out"), (dir / tag).string()})
    argv.push_back(a);
  const test::Outcome r = test::run_process(argv, dir, tag);
  EXPECT_EQ(r.code, 0) << r.err;
  return Json::parse(test::read_text(dir / tag / "identified.json"));
}

TEST(IdentifyMpi, ThreeRanksShareTheStartsAndGiveTheSingleProcessFitToTheBit) {
  const fs::path dir = test::scratch_dir("identify_mpi", "starts");
  // OpenMPI refuses root unless told, and 2 ranks may exceed the slots of a small machine.
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
  const Json one = fit_three_starts(dir, "one", {});
  const Json mpi = fit_three_starts(dir, "mpi", {CAMDYN_MPIEXEC, "-np", "3"});
  ASSERT_EQ(one["starts"].size(), 3u);
  EXPECT_EQ(one["final_cost"], one["starts"][2]["final_cost"]);  // the start another rank ran
  for (const char* key : {"starts", "parameters", "final_cost", "initial_cost", "simulations", "iterations",
                          "reused_points", "stages", "poor_fit", "identifiable", "correlation", "jacobian"}) {
    SCOPED_TRACE(key);
    EXPECT_EQ(mpi[key], one[key]);
  }
}

}  // namespace
}  // namespace camdyn::optim
