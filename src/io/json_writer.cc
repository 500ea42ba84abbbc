#include "io/json_writer.h"

#include <cmath>
#include <stdexcept>

#include "io/atomic_file.h"

namespace camdyn {
namespace {

// RFC 6901: '~' and '/' inside a key are written "~0" and "~1".
std::string escape_pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out.push_back(c);
    }
  }
  return out;
}

template <class J>
void check_finite(const J& node, std::string& pointer) {
  if (node.is_number_float()) {
    const double v = node.template get<double>();
    if (!std::isfinite(v)) {
      throw std::logic_error("non-finite number " + std::to_string(v) + " in JSON output at '" +
                             (pointer.empty() ? std::string("/") : pointer) + "'");
    }
  } else if (node.is_object() || node.is_array()) {
    std::size_t index = 0;
    for (auto it = node.begin(); it != node.end(); ++it, ++index) {
      const std::size_t mark = pointer.size();
      pointer += '/';
      pointer += node.is_object() ? escape_pointer_token(it.key()) : std::to_string(index);
      check_finite(it.value(), pointer);
      pointer.resize(mark);
    }
  }
}

template <class J>
std::string dump_checked(const J& doc) {
  std::string pointer;
  check_finite(doc, pointer);
  // Invalid UTF-8 is replaced rather than thrown on: a user's label must not lose a result.
  return doc.dump(2, ' ', false, J::error_handler_t::replace) + "\n";
}

template <class J>
void write_checked(const std::filesystem::path& path, const J& doc) {
  std::string text;
  try {
    text = dump_checked(doc);
  } catch (const std::logic_error& e) {
    throw std::logic_error(path.string() + ": " + e.what());
  }
  write_file_atomic(path, text);
}

}  // namespace

void check_json_finite(const nlohmann::ordered_json& doc) {
  std::string pointer;
  check_finite(doc, pointer);
}

void check_json_finite(const nlohmann::json& doc) {
  std::string pointer;
  check_finite(doc, pointer);
}

std::string dump_json(const nlohmann::ordered_json& doc) { return dump_checked(doc); }
std::string dump_json(const nlohmann::json& doc) { return dump_checked(doc); }

void write_json_atomic(const std::filesystem::path& path, const nlohmann::ordered_json& doc) {
  write_checked(path, doc);
}

void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc) { write_checked(path, doc); }

}  // namespace camdyn
