#include "study/convergence_study.h"

#include "common/errors.h"

namespace camdyn {

int run_convergence_study(const Json&, const StudyContext& ctx) {
  throw InputError(ctx.config_file, "study", "the convergence study is not available in this version of camdyn");
}

}  // namespace camdyn
