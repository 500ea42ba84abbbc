// The contact stiffness resolved from materials (docs/config.md, "Outputs of
// `simulate`"): `camdyn validate` prints it and a run writes it as
// summary.json `resolved.contact_stiffness`, the line-contact closed form
// K = π/4 E* w with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "cli_run.h"
#include "study_paths.h"

namespace {

TEST(ResolvedStiffness, ValidatePrintsItAndTheSummaryHoldsIt) {
  const std::filesystem::path dir = camdyn::test::scratch_dir("resolved_stiffness_cli_test", "bucket");
  const std::string bucket = kStudies + "valvetrain/bucket_tappet.json";
  // The bucket's steel on steel (E 2.1e11 Pa, ν 0.3) over a 12 mm line.
  const double e_star = 1.0 / (2.0 * (1.0 - 0.3 * 0.3) / 2.1e11);
  const double k = std::numbers::pi / 4.0 * e_star * 0.012;  // [N/m]
  const camdyn::test::Outcome v = camdyn::test::run_camdyn({"validate", bucket}, dir);
  ASSERT_EQ(v.code, 0) << v.err;
  const std::string::size_type at = v.err.find("resolved: contact stiffness ");
  ASSERT_NE(at, std::string::npos) << v.err;
  const double printed = std::stod(v.err.substr(at + std::string("resolved: contact stiffness ").size()));
  EXPECT_NEAR(printed, k, 1e-5 * k);  // printed to 6 significant digits
  const camdyn::test::Outcome r =
      camdyn::test::run_camdyn({"run", bucket, "--quiet", "--set", "simulation.cycles=1", "--set",
                                "simulation.discard_cycles=0", "--out", (dir / "out").string()},
                               dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto summary = nlohmann::json::parse(camdyn::test::read_text(dir / "out" / "summary.json"));
  EXPECT_NEAR(summary["resolved"]["contact_stiffness"].get<double>(), k, 1e-14 * k);
  EXPECT_EQ(summary["resolved"]["contact_stiffness_from"], "materials");
  // Without materials it is the stiffness given.
  const camdyn::test::Outcome q =
      camdyn::test::run_camdyn({"run", kQuickstart, "--quiet", "--set", "simulation.cycles=1", "--set",
                                "simulation.discard_cycles=0", "--out", (dir / "quickstart").string()},
                               dir);
  ASSERT_EQ(q.code, 0) << q.err;
  const auto plain = nlohmann::json::parse(camdyn::test::read_text(dir / "quickstart" / "summary.json"));
  EXPECT_EQ(plain["resolved"]["contact_stiffness"], plain["config"]["mechanism"]["contact"]["stiffness"]);
  EXPECT_EQ(plain["resolved"]["contact_stiffness_from"], "config");
}

}  // namespace
