// Dotted paths into a config document ("mechanism.cam.motion_law.segments[0].lift"):
// how `--set`, compare grids and cases, and identify's parameters name a field.
// One parser turns the text into steps (object keys and array indices); find
// and set walk a Json document along them. A leading `cam`, `follower` or
// `contact` is short for `mechanism.cam` etc.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/config.h"

namespace camdyn {

/// One step of a dotted path: an object key, or an array index.
struct PathStep {
  std::string key;        ///< empty for an index
  std::size_t index = 0;  ///< the array index when `key` is empty

  bool is_index() const { return key.empty(); }
};

/// "a.b[2].c" → {"a", "b", 2, "c"}; a leading cam/follower/contact gets
/// "mechanism" put in front. Keys are letters, digits and '_'. Bad syntax throws
/// InputError("--set", path, reason + " (expected a dotted path like ...)").
std::vector<PathStep> parse_dotted_path(const std::string& path);

/// The path with the short form expanded: "cam.rpm" → "mechanism.cam.rpm"
/// (any other path unchanged, bad syntax included).
std::string full_dotted_path(const std::string& path);

/// The field at `path` in `document`, or null with `why` saying which step is
/// missing ("'x' is not a field of 'mechanism.cam' (did you mean ...)", "'a.b' has
/// no element 3") or why the path cannot be parsed.
const Json* find_dotted_field(const Json& document, const std::string& path, std::string& why);

/// Sets the field at `path` to `value`, creating missing object keys (and
/// turning a null on the way into an object). Throws InputError("--set", path,
/// reason) for bad syntax, a step into something that is not an object or an
/// array, or an index out of range.
void set_dotted_field(Json& document, const std::string& path, const Json& value);

}  // namespace camdyn
