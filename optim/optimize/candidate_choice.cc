#include "optim/optimize/candidate_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace camdyn::optim {

namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// "the baseline", "the rigid design", "the dynamic result".
std::string noun(CandidateKind kind) {
  switch (kind) {
    case CandidateKind::rigid:
      return "the rigid design";
    case CandidateKind::dynamic:
      return "the dynamic result";
    case CandidateKind::spring:
      return "the sized spring";
    case CandidateKind::baseline:
      break;
  }
  return "the baseline";
}

/// What a candidate that lost was, in a few words.
std::string describe(const CandidateScore& c) {
  const std::string name = noun(c.kind);
  if (!c.available) return "";
  if (!c.valid) return name + " could not be simulated";
  if (!c.feasible) return name + " breaks " + joined(c.violated);
  return name + " objective " + number(c.objective);
}

/// a is better than b: feasible first, then the lower objective, or (both
/// infeasible) the smaller violation.
bool better(const CandidateScore& a, const CandidateScore& b) {
  if (a.feasible != b.feasible) return a.feasible;
  if (a.feasible) return a.objective < b.objective;
  return a.violation < b.violation;
}

}  // namespace

const char* to_string(CandidateKind kind) {
  switch (kind) {
    case CandidateKind::baseline:
      return "baseline";
    case CandidateKind::rigid:
      return "rigid";
    case CandidateKind::dynamic:
      return "dynamic";
    case CandidateKind::spring:
      return "spring";
  }
  return "baseline";
}

CandidateChoice choose_candidate(const std::vector<CandidateScore>& candidates) {
  const auto base_it = std::find_if(candidates.begin(), candidates.end(),
                                    [](const CandidateScore& c) { return c.kind == CandidateKind::baseline; });
  CandidateScore base = base_it != candidates.end() ? *base_it : CandidateScore{};
  // The baseline's objective less the tolerance is what a challenger must beat.
  CandidateScore bar = base;
  if (bar.feasible) bar.objective -= kBeatTolerance * std::max(std::abs(base.objective), 1e-12);
  const CandidateScore* best = nullptr;
  for (const CandidateScore& c : candidates) {
    if (!c.available || !c.valid || c.kind == CandidateKind::baseline) continue;
    if (!better(c, bar)) continue;
    if (!best || better(c, *best)) best = &c;
  }
  CandidateChoice out;
  const CandidateScore& chosen = best ? *best : base;
  out.chosen = chosen.kind;
  out.feasible = chosen.valid && chosen.feasible;
  // Feasible where the baseline is not, or lower on the objective (the rule of `better`).
  out.beats_baseline = best != nullptr && chosen.feasible && (!base.feasible || chosen.objective < base.objective);
  std::string others;
  for (const CandidateScore& c : candidates) {
    if (&c == best || c.kind == chosen.kind) continue;
    const std::string d = describe(c);
    if (!d.empty()) others += (others.empty() ? "" : "; ") + d;
  }
  if (!out.feasible)
    out.reason = "no candidate meets every constraint; " + noun(chosen.kind) + " breaks the least (" +
                 joined(chosen.violated) + ")";
  else if (!best)
    out.reason = "no candidate beats the baseline (objective " + number(base.objective) + ") with every constraint";
  else
    out.reason = noun(chosen.kind) + " meets every constraint with the lowest objective, " + number(chosen.objective);
  if (!others.empty()) out.reason += " (" + others + ")";
  return out;
}

}  // namespace camdyn::optim
