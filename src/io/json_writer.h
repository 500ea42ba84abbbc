// JSON output (summary.json, result.json, ...): 2-space indent, written
// atomically. nlohmann::json would silently print a NaN or infinity as
// `null`; the interface promises no NaN in an output file, so such a document
// is refused with a std::logic_error naming the JSON pointer of the value.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace camdyn {

/// Throws std::logic_error if any number in `doc` is NaN or infinite.
void check_json_finite(const nlohmann::ordered_json& doc);
void check_json_finite(const nlohmann::json& doc);

/// The checked document as text, 2-space indent, ending in a newline.
std::string dump_json(const nlohmann::ordered_json& doc);
std::string dump_json(const nlohmann::json& doc);

/// Checks `doc` and writes it to `path` through write_file_atomic.
void write_json_atomic(const std::filesystem::path& path, const nlohmann::ordered_json& doc);
void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc);

}  // namespace camdyn
