// report.html of the `periodic` study: the verdict first, then the orbit in
// the phase plane with its Poincaré points, the contact force over one
// period, the cam (output/cam_plots.h), the Floquet multipliers against the unit
// circle and the Newton residuals of the search.
#pragma once

#include "dynamics/poincare_map.h"
#include "output/report.h"
#include "study/periodic_study.h"

namespace camdyn {

Report periodic_report(const PeriodicStudy& study, const PeriodicResult& r, const PoincareMap& map);

}  // namespace camdyn
