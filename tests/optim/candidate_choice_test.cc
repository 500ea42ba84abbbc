// The choice of an optimize study's answer (optim/optimize/candidate_choice.h):
// never worse than the baseline on its own objective, feasible before
// infeasible, the least violation when nothing is feasible.
#include "optim/optimize/candidate_choice.h"

#include <gtest/gtest.h>

#include <vector>

namespace camdyn::optim {
namespace {

CandidateScore feasible(CandidateKind kind, double objective) {
  CandidateScore c;
  c.kind = kind;
  c.available = c.valid = c.feasible = true;
  c.objective = objective;
  return c;
}

CandidateScore breaking(CandidateKind kind, double objective, double violation) {
  CandidateScore c = feasible(kind, objective);
  c.feasible = false;
  c.violation = violation;
  c.violated = {"no_separation_where_proven"};
  return c;
}

TEST(CandidateChoice, AWorseSearchResultKeepsTheBaseline) {
  const CandidateChoice c =
      choose_candidate({feasible(CandidateKind::baseline, 1.00005), feasible(CandidateKind::rigid, 1.00040),
                        feasible(CandidateKind::dynamic, 1.00035)});
  EXPECT_EQ(c.chosen, CandidateKind::baseline);
  EXPECT_TRUE(c.feasible);
  EXPECT_FALSE(c.beats_baseline);
  EXPECT_NE(c.reason.find("no candidate beats the baseline"), std::string::npos) << c.reason;
}

TEST(CandidateChoice, ATieWithinTheToleranceKeepsTheBaseline) {
  const double base = 2.0;
  const CandidateChoice c = choose_candidate(
      {feasible(CandidateKind::baseline, base), feasible(CandidateKind::dynamic, base * (1 - 0.5 * kBeatTolerance))});
  EXPECT_EQ(c.chosen, CandidateKind::baseline);
}

TEST(CandidateChoice, TheLowestFeasibleObjectiveWins) {
  const CandidateChoice c =
      choose_candidate({feasible(CandidateKind::baseline, 1.0), feasible(CandidateKind::rigid, 0.8),
                        breaking(CandidateKind::dynamic, 0.5, 0.1)});
  EXPECT_EQ(c.chosen, CandidateKind::rigid);
  EXPECT_TRUE(c.beats_baseline);
  EXPECT_NE(c.reason.find("the dynamic result breaks no_separation_where_proven"), std::string::npos) << c.reason;
}

TEST(CandidateChoice, AFeasibleDesignBeatsAnInfeasibleBaselineWhateverItsObjective) {
  const CandidateChoice c =
      choose_candidate({breaking(CandidateKind::baseline, 0.1, 3.0), feasible(CandidateKind::dynamic, 5.0)});
  EXPECT_EQ(c.chosen, CandidateKind::dynamic);
  EXPECT_TRUE(c.feasible);
  EXPECT_TRUE(c.beats_baseline);  // the green banner: it holds what the baseline breaks
}

TEST(CandidateChoice, NothingFeasibleGivesTheLeastViolationAndSaysSo) {
  CandidateScore missing;
  missing.kind = CandidateKind::rigid;  // no rigid design
  const CandidateChoice c = choose_candidate(
      {breaking(CandidateKind::baseline, 1.0, 0.5), missing, breaking(CandidateKind::dynamic, 1.0, 0.2)});
  EXPECT_EQ(c.chosen, CandidateKind::dynamic);
  EXPECT_FALSE(c.feasible);
  EXPECT_FALSE(c.beats_baseline);
  EXPECT_NE(c.reason.find("no candidate meets every constraint"), std::string::npos) << c.reason;
}

TEST(CandidateChoice, AnInvalidCandidateIsNeverChosen) {
  CandidateScore invalid = feasible(CandidateKind::dynamic, 0.0);
  invalid.valid = false;
  const CandidateChoice c = choose_candidate({breaking(CandidateKind::baseline, 1.0, 1.0), invalid});
  EXPECT_EQ(c.chosen, CandidateKind::baseline);
  EXPECT_FALSE(c.feasible);
}

}  // namespace
}  // namespace camdyn::optim
