#include "optim/optimize_study.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "common/errors.h"
#include "io/json_writer.h"
#include "io/report.h"
#include "optim/optimize.h"
#include "optim/optimize_config.h"
#include "optim/optimize_output.h"

namespace camdyn::optim {

int run_optimize_study(const Json& doc, const StudyContext& ctx) {
  const OptimizeStudy study = read_optimize_study(doc, ctx.source);
  const SceneConfig& baseline = study.baseline;
  const OptimizeStudyConfig& config = study.config;
  check_optimize(baseline, config, ctx.config_file);
  if (ctx.validate_only) {
    std::cout << dump_json(resolved_study_json(baseline, "optimize", to_json(config)));
    std::cerr << "camdyn: " << ctx.config_file << " is valid (optimize: " << config.operating_rpm.size()
              << " operating speeds, " << config.optimizer.algorithm << ")\n";
    return 0;
  }

  OptimizeOptions options;
  options.threads = ctx.threads();
  options.progress = ctx.progress;
  const OptimizeOutcome o = run_optimize(baseline, config, ctx.config_file, options);
  write_optimize_outputs(ctx.out_dir, o, baseline.name, ctx.config_file);

  const auto& b = o.baseline;
  const auto& p = o.optimized;
  std::printf("%s: %s, %ld evaluations (%ld invalid), stop reason %s, %.3g s\n", baseline.name.c_str(),
              o.search.method.c_str(), o.search.evaluations, o.search.invalid_evaluations, o.search.stop_reason.c_str(),
              o.run_time_s);
  std::printf("  objective %.6g -> %.6g; constraints %s\n", b.objective, p.objective,
              p.feasible ? "all hold" : "VIOLATED (see result.json)");
  for (std::size_t i = 0; i < b.speeds.size() && i < p.speeds.size(); ++i) {
    const Metrics& mb = b.speeds[i].result.metrics;
    const Metrics& mp = p.speeds[i].result.metrics;
    std::printf(
        "  %6g rpm: separation_fraction %.4g -> %.4g, peak_contact_force %.6g -> %.6g N, "
        "min_contact_force %.6g -> %.6g N\n",
        b.speeds[i].rpm, mb.separation_fraction, mp.separation_fraction, mb.peak_contact_force, mp.peak_contact_force,
        mb.min_contact_force, mp.min_contact_force);
  }
  const auto abs_out = std::filesystem::absolute(ctx.out_dir).lexically_normal();
  std::printf("  optimised config: %s\n", (abs_out / "optimized.json").c_str());
  std::printf("  report: %s\n", (abs_out / "report.html").c_str());
  return 0;
}

}  // namespace camdyn::optim
