// What a camdyn::Scene (<camdyn/scene.h>) holds behind its pointer: the typed
// scene and the model built from it once, when the scene is loaded. Private
// to src/api/.
#pragma once

#include <camdyn/scene.h>

#include <string>

#include "common/errors.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "scene/scene.h"

namespace camdyn {

struct Scene::Impl {
  /// The typed scene and its model (which checks what the config layer
  /// cannot: the motion law, the cam geometry and the contact law), as
  /// `camdyn run` and `camdyn validate` build them. Throws InputError.
  Impl(const Json& document, const ConfigSource& from);
  /// The scene of `document` (the resolved config of `previous` with one
  /// field changed), its model assembled on previous's geometry when the
  /// change leaves the geometry as it is (dynamics/cam_geometry.h).
  Impl(const Json& document, const Impl& previous);

  SceneConfig scene;
  ConfigSource source;  ///< where the config came from, and its relative paths resolve
  std::string file;     ///< the config file, for messages; empty for Scene::from_json
  Model model;
};

/// Runs `f` and returns what it returns; an InputError that names no file
/// (raised below the config layer) is thrown again naming `file`, as the CLI
/// reports it.
template <class F>
auto naming_file(const std::string& file, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    if (!e.file().empty() || file.empty()) throw;
    throw InputError(file, e.path(), e.reason());
  }
}

}  // namespace camdyn
