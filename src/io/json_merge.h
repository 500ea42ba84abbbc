// Deep merge of JSON documents: how a config that `extends` another one, and a
// compare case's inline `config`, are laid over their base. Objects merge key
// by key (the patch wins); anything else, and the paths named "replaced
// whole", is replaced by the patch.
#pragma once

#include <string>
#include <vector>

#include "io/config.h"

namespace camdyn {

/// Merges `patch` into `base`. `replaced_whole` lists dotted paths
/// ("mechanism.cam.motion_law") whose value the patch replaces instead of
/// merging into, even when both are objects.
void deep_merge(Json& base, const Json& patch, const std::vector<std::string>& replaced_whole = {});

/// The merge of configs: deep_merge with the motion law replaced whole (it is
/// one thing: switching from segments to a table must not leave both).
void merge_config(Json& base, const Json& patch);

}  // namespace camdyn
