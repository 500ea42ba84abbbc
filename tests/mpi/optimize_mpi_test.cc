// The starts of an optimize study spread over `mpirun -np 2` (start s on rank
// s mod 2; optim/search.h SearchProblem::over_ranks) give the single
// process's answer to the bit: the same optimized.json, history.csv (every
// evaluation, in start order, with its objective and best so far) and
// result.json (timings aside), and only rank 0 writes outputs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"
#include "io/config.h"
#include "optimize_study_text.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

/// result.json without what the clock decides (run times and rates).
Json without_timings(Json j) {
  if (j.is_object()) {
    Json out = Json::object();
    for (auto& [key, value] : j.items()) {
      const bool timing = key.find("time_s") != std::string::npos || key.find("per_second") != std::string::npos;
      if (!timing) out[key] = without_timings(value);
    }
    return out;
  }
  if (j.is_array())
    for (Json& item : j) item = without_timings(item);
  return j;
}

/// The study file: three starts of COBYLA (24 evaluations) on the quickstart
/// splines, the rigid stage off; its relative paths made absolute.
fs::path write_study(const fs::path& dir) {
  std::string fields = quickstart_force_design_fields();
  const std::string relative = "\"profiles/";
  fields.replace(fields.find(relative), relative.size(), "\"" + std::string(CAMDYN_SOURCE_DIR) + "/profiles/");
  fs::path study = dir / "study.json";
  std::ofstream(study) << R"({ "name": "mpi_optimize", "study": "optimize",)" << fields << R"(
    "rigid": { "enabled": false },
    "optimizer": { "algorithm": "LN_COBYLA", "max_evaluations": 24, "starts": 3, "seed": 7 } })";
  return study;
}

TEST(OptimizeMpi, TwoRanksShareTheStartsAndGiveTheSingleProcessAnswerToTheBit) {
  const fs::path dir = test::scratch_dir("optimize_mpi", "starts");
  const fs::path study = write_study(dir);
  // OpenMPI refuses root unless told, and 2 ranks may exceed the slots of a small machine.
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
  const test::Outcome one =
      test::run_camdyn({"run", study.string(), "--jobs", "1", "--out", (dir / "one").string()}, dir, "one");
  ASSERT_EQ(one.code, 0) << one.err;
  const test::Outcome mpi = test::run_process({CAMDYN_MPIEXEC, "-np", "2", CAMDYN_BINARY, "run", study.string(),
                                               "--jobs", "1", "--out", (dir / "mpi").string()},
                                              dir, "mpi");
  ASSERT_EQ(mpi.code, 0) << mpi.err;
  EXPECT_EQ(mpi.err.find("rank 0 alone"), std::string::npos) << mpi.err;
  const std::string history = test::read_text(dir / "one" / "history.csv");
  EXPECT_EQ(std::count(history.begin(), history.end(), '\n'), 25);  // the header and 24 evaluations
  EXPECT_EQ(test::read_text(dir / "mpi" / "history.csv"), history);
  EXPECT_EQ(test::read_text(dir / "mpi" / "optimized.json"), test::read_text(dir / "one" / "optimized.json"));
  const Json result = without_timings(Json::parse(test::read_text(dir / "one" / "result.json")));
  EXPECT_EQ(without_timings(Json::parse(test::read_text(dir / "mpi" / "result.json"))), result);
  // Every start ran (start 1 on rank 1), and rank 0 journaled each distinct design once.
  const std::string journal = test::read_text(dir / "one" / "journal.jsonl");
  EXPECT_EQ(test::read_text(dir / "mpi" / "journal.jsonl").size(), journal.size());
}

}  // namespace
}  // namespace camdyn::optim
