#include "optim/identify_study.h"

#include "common/errors.h"

namespace camdyn::optim {

int run_identify_study(const Json&, const StudyContext& ctx) {
  throw InputError(ctx.config_file, "study", "the identify study is not available in this version of camdyn");
}

}  // namespace camdyn::optim
