// The identify report gives the follower signals, their misfits and the
// parameters measured along the follower coordinate in its unit: rad, rad/s,
// N m/rad for an oscillating arm, m, m/s, N/m for a translating follower
// (dynamics/coordinate_units.h). Contact signals stay in N.
#include "optim/identify/identify_output.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/dynamics/scenes.h"

namespace camdyn::optim {
namespace {

const std::vector<std::string> kSignals = {"follower_position", "follower_velocity", "follower_acceleration",
                                           "contact_force"};

/// A fitted spring stiffness and one record of kSignals, on `kind`'s follower (scenes.h).
struct OneRecordFit {
  IdentifyProblem problem;
  IdentifyResult result;

  explicit OneRecordFit(const std::string& kind) {
    problem.config_file = "test";
    problem.scene = test::follower_scene(kind, 1000.0);
    FitExperiment e;
    e.name = "record";
    e.reference.file = "record.csv";
    e.scene = problem.scene;
    problem.experiments.push_back(e);
    ParameterEstimate p;
    p.name = p.path = "mechanism.follower.spring.stiffness";
    p.value = 50.0;
    p.initial = 40.0;
    p.std_error = 1.0;
    result.parameters = {p};
    result.correlation = {{1.0}};
    ExperimentFit fit;
    fit.name = "record";
    fit.time = {0.0, 1e-3};
    fit.signals = kSignals;
    fit.measured = fit.fitted = std::vector<std::vector<double>>(kSignals.size(), {1.0, 2.0});
    fit.weights = fit.rms_error = fit.noise = std::vector<double>(kSignals.size(), 0.5);
    result.fits = {fit};
    result.identified_scene = problem.scene;
  }
};

const Table& table_titled(const Report& report, const std::string& prefix) {
  for (const Table& t : report.tables)
    if (t.title.rfind(prefix, 0) == 0) return t;
  ADD_FAILURE() << "no table " << prefix;
  return report.tables.front();
}

std::vector<std::string> ylabels(const Report& report, const std::string& title) {
  std::vector<std::string> labels;
  for (const Plot& p : report.plots)
    if (p.title == title) labels.push_back(p.ylabel);
  return labels;
}

TEST(IdentifyReport, ArmsFollowerSignalsAndSpringAreInRad) {
  const OneRecordFit f("oscillating_roller");
  const Report report = identify_report(f.problem, f.result);
  EXPECT_EQ(table_titled(report, "Identified parameters").rows[0][0], "mechanism.follower.spring.stiffness [N m/rad]");
  const Table& records = table_titled(report, "Records");
  ASSERT_EQ(records.rows.size(), kSignals.size());
  const std::vector<std::string> units = {"rad", "rad/s", "rad/s²", "N"};
  for (std::size_t s = 0; s < kSignals.size(); ++s) {
    EXPECT_EQ(records.rows[s][5], "0.5 " + units[s]) << kSignals[s];  // RMS misfit
    EXPECT_EQ(records.rows[s][6], "0.5 " + units[s]) << kSignals[s];  // noise estimate
    const std::string label = kSignals[s] + " [" + units[s] + "]";
    EXPECT_EQ(ylabels(report, "record: " + kSignals[s] + ", measured and fitted"), std::vector<std::string>{label});
    EXPECT_EQ(ylabels(report, "record: " + kSignals[s] + ", residual (fitted − measured)"),
              std::vector<std::string>{label});
  }
  EXPECT_EQ(records.rows[0][4], "0.5 1/rad");  // weight
}

TEST(IdentifyReport, TranslatingFollowerSignalsAndSpringAreInMetres) {
  const OneRecordFit f("translating_roller");
  const Report report = identify_report(f.problem, f.result);
  EXPECT_EQ(table_titled(report, "Identified parameters").rows[0][0], "mechanism.follower.spring.stiffness [N/m]");
  const Table& records = table_titled(report, "Records");
  EXPECT_EQ(records.rows[0][5], "0.5 m");
  EXPECT_EQ(records.rows[1][5], "0.5 m/s");
  EXPECT_EQ(records.rows[2][5], "0.5 m/s²");
  EXPECT_EQ(ylabels(report, "record: follower_position, measured and fitted"),
            std::vector<std::string>{"follower_position [m]"});
}

}  // namespace
}  // namespace camdyn::optim
