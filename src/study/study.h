// What every study type (simulate, optimize, identify, compare, convergence)
// gets from the command line, and the split of a study config into the scene
// it is built on (the common part of docs/config.md) and its own fields.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/config.h"
#include "io/json_archive.h"

namespace camdyn {

struct StudyContext {
  std::string config_file;        ///< as given on the command line (for messages)
  ConfigSource source;            ///< file and directory relative paths resolve against
  std::filesystem::path out_dir;  ///< output folder (default out/<name>)
  int jobs = 0;                   ///< parallel jobs; 0 = one per core
  bool progress = false;          ///< draw progress on stderr
  bool validate_only = false;     ///< `camdyn validate`: check, print the resolved config, do not run
  bool strict = false;            ///< `camdyn run --strict`: plausibility warnings exit 3 (docs/warnings.md)

  /// Number of worker threads to use: `jobs`, or the number of cores.
  int threads() const;
};

/// Splits a study config: the keys in `study_keys` go to `study_part`; the
/// rest must be a valid scene (checked by scene_from_json as a `simulate`
/// scene, so unknown keys are errors there). Throws InputError.
SceneConfig scene_from_study_json(const Json& doc, const ConfigSource& source,
                                  const std::vector<std::string>& study_keys, Json& study_part);

/// Reads the object `part[key]` ({} when absent) into `fields` through their
/// `visit`, so unknown keys and bad values are InputErrors naming `key.field`;
/// returns the fields written back, every default filled in (the resolved config).
template <class Fields>
Json read_study_fields(const Json& part, const std::string& key, const ConfigSource& source, Fields& fields) {
  const Json object = part.value(key, Json::object());  // the reader keeps a reference
  JsonReader reader(object, key, source);
  visit(reader, fields);
  reader.finish();
  JsonWriter writer;
  visit(writer, fields);
  return writer.json();
}

/// The resolved config of a study: the resolved scene, the study name and the
/// study's own resolved fields.
Json resolved_study_json(const SceneConfig& scene, const std::string& study, const Json& study_part);

}  // namespace camdyn
