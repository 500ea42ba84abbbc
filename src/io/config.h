// Loading a scene (scene/scene.h) from its JSON config and printing it back:
// io/config.cc maps each struct to and from JSON in exactly one function that
// lists every field, so unknown keys are rejected and the fully resolved
// config can be printed back. File names and dotted paths for error messages
// are added here, at the boundary.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace camdyn {

using Json = nlohmann::ordered_json;

/// A scene enum in a JSON document is its config word (never its number:
/// the build defines JSON_DISABLE_ENUM_SERIALIZATION, so an enum without a
/// name table cannot reach a JSON document by accident).
template <class BasicJson, NamedEnum E>
void to_json(BasicJson& json, E value) {
  json = std::string(enum_name(value));
}

/// The fastest cam a speed field accepts [rpm]: beyond it the speed is a
/// slip (rad/s for rpm, a sweep's end of 1e308) whose products with the
/// other inputs (ω², ω³ of the rigid-model force) overflow.
inline constexpr double kMaxCamRpm = 1e6;
/// The slowest turning cam a speed field accepts [rpm] (0, a cam at rest, is
/// a scene's own choice): a revolution in about 17 hours. Slower, a run's
/// time grid outgrows double precision (5e-324 rpm ran without end).
inline constexpr double kMinCamRpm = 1e-3;

// ---------------------------------------------------------------- loading

/// Where a config came from: the file (for error messages and relative paths).
struct ConfigSource {
  std::string file;  ///< path as given by the user
  std::string dir;   ///< directory that relative paths in it are resolved against

  bool operator==(const ConfigSource&) const = default;
};

/// Reads a JSON file, resolves `extends` (paths relative to each file), applies
/// `--set KEY=VALUE` overrides (VALUE parsed as JSON, else taken as a string),
/// and returns the merged JSON document. Throws InputError (file, dotted path, reason).
Json load_config_json(const std::string& file, const std::vector<std::string>& overrides = {});

/// Maps a merged JSON document to a SceneConfig, rejecting unknown keys (with the
/// closest valid key suggested), wrong types and out-of-range values, and
/// resolving `motion_law` given as a profile path and `table.file`.
SceneConfig scene_from_json(const Json& json, const ConfigSource& source);

/// Reads the rows of a lift table's CSV file (`table.file`, its angle and lift
/// columns) into `table.angle_deg`, `table.lift` and `table.lines`; called by
/// scene_from_json. Throws InputError naming the CSV file and line.
void load_table_rows(TableConfig& table);

/// Reads a gas load's pressure table (`gas.pressure`, columns `crank_deg`
/// and `pressure`, at least 2 rows) into its rows; `at` is its dotted path
/// for messages. The loader calls it for every train body with a gas load.
void load_gas_table_rows(GasLoadConfig& gas, const std::string& at);

/// The fully resolved config (every field, defaults filled in).
Json to_json(const SceneConfig& scene);

/// Sets `dotted_path` (e.g. "mechanism.cam.rpm", "mechanism.cam.motion_law.segments[0].lift";
/// a leading "cam.", "follower." or "contact." means "mechanism.…") in a config
/// document to `value`, creating missing objects on the way; array elements
/// must exist. Throws InputError("--set", dotted_path, reason). Unknown keys
/// are left for scene_from_json to reject.
void set_config_value(Json& document, const std::string& dotted_path, const Json& value);

/// Applies one "dotted.path=VALUE" assignment (VALUE parsed as JSON if it
/// parses, else taken as a string), as `--set` does.
void apply_assignment(Json& document, const std::string& assignment);

/// The last of `overrides` ("dotted.path=VALUE") that set the field at
/// `path` (a full dotted path as an InputError names it) or an object or
/// array above it; nullopt if the field came from the file. So an error in a
/// value given on the command line can name that `--set` argument.
std::optional<std::string> assignment_setting(const std::vector<std::string>& overrides, const std::string& path);

/// The source of a config file: the file and the directory its relative paths resolve against.
ConfigSource config_source(const std::string& file);

/// load_config_json + scene_from_json.
SceneConfig load_scene(const std::string& file, const std::vector<std::string>& overrides = {});

}  // namespace camdyn
