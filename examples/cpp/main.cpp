// Loads a scene, simulates it and prints a few metrics, through camdyn's
// public API only: app [CONFIG [KEY=VALUE ...]] (default studies/quickstart.json).
#include <camdyn/camdyn.h>

#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  const std::string config = argc > 1 ? argv[1] : "studies/quickstart.json";
  const std::vector<std::string> overrides(argv + (argc > 1 ? 2 : 1), argv + argc);
  try {
    const camdyn::Scene scene = camdyn::Scene::load(config, overrides);
    const camdyn::Result result = camdyn::simulate(scene);
    std::printf("camdyn %s\n", camdyn::kVersion);
    std::printf("%s at %g rpm: %s (rigid-model jump speed %.6g rpm)\n", scene.name().c_str(), scene.rpm(),
                camdyn::termination_name(result.solver.termination), scene.jump_speed_rpm());
    std::printf("  separation_fraction %.4g, impacts %g, peak_contact_force %.6g N\n",
                result.metrics.at("separation_fraction"), result.metrics.at("impact_count"),
                result.metrics.at("peak_contact_force"));
    std::printf("  %zu output rows, %zu contact events, %ld steps\n", result.series.rows(), result.events.size(),
                result.solver.steps);
    camdyn::throw_if_failed(result);
  } catch (const camdyn::InputError& e) {
    std::fprintf(stderr, "invalid input: %s\n", e.what());
    return 2;
  } catch (const camdyn::NumericalError& e) {
    std::fprintf(stderr, "numerical failure: %s\n", e.what());
    return 3;
  }
  return 0;
}
