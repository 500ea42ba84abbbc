// camdyn as a C++ library: everything a caller needs, in one include.
//
//     #include <camdyn/camdyn.h>
//     const camdyn::Scene scene = camdyn::Scene::load("studies/quickstart.json");
//     const camdyn::Result result = camdyn::simulate(scene);
//     std::cout << result.metrics.at("peak_contact_force") << " N\n";
//
// CMake: find_package(camdyn 0.2 REQUIRED), target_link_libraries(app camdyn::camdyn).
// See docs/library.md.
#pragma once

#include <camdyn/errors.h>
#include <camdyn/scene.h>
#include <camdyn/simulate.h>
#include <camdyn/version.h>
