// libFuzzer target: the config loader, as `camdyn validate` runs it. The
// input is a study config, optionally followed by more files and `--set`
// arguments, each after a line "#--- NAME":
//
//   { "extends": "base.json", "study": "compare", ... }
//   #--- base.json
//   { "mechanism": { ... } }
//   #--- --set
//   mechanism.cam.rpm=1200
//
// The first part is written to main.json and the named parts beside it in a
// scratch folder, so `extends`, profiles and data files resolve there. The
// config goes through run_study (read, extends, --set, the study's own
// validation: simulate, compare grids, optimize, identify, periodic,
// jump_map, convergence, speed_limit), which must end normally or with a
// camdyn error (fuzz_support.h).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cli/run_study.h"
#include "fuzz_support.h"

namespace {

constexpr std::string_view kSectionMark = "#--- ";
constexpr std::size_t kMaxNameLength = 40;

// A file name the scratch folder can hold: letters, digits, '_', '-' and '.',
// not starting with '.'; "" if `name` is not one.
std::string safe_name(std::string_view name) {
  if (name.empty() || name.size() > kMaxNameLength || name.front() == '.') return "";
  for (const char c : name) {
    const bool ok =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
    if (!ok) return "";
  }
  return std::string(name);
}

struct Parts {
  std::string main;
  std::vector<std::string> overrides;
};

// Splits the input into main.json, the named files (written to the scratch
// folder) and the --set lines.
Parts split_input(std::string_view input, const camdyn::fuzz::Scratch& scratch) {
  Parts parts;
  std::string name = "main.json", text;
  auto flush = [&] {
    if (name == "main.json") {
      parts.main = text;
    } else if (name == "--set") {
      std::size_t begin = 0;
      while (begin < text.size()) {
        std::size_t end = text.find('\n', begin);
        if (end == std::string::npos) end = text.size();
        if (end > begin) parts.overrides.emplace_back(text.substr(begin, end - begin));
        begin = end + 1;
      }
    } else if (const std::string file = safe_name(name); !file.empty()) {
      scratch.write(file, text);
    }
    text.clear();
  };
  std::size_t begin = 0;
  while (begin < input.size()) {
    std::size_t end = input.find('\n', begin);
    const std::size_t next = end == std::string_view::npos ? input.size() : end + 1;
    const std::string_view line = input.substr(begin, next - begin);
    if (line.starts_with(kSectionMark)) {
      flush();
      std::string_view header = line.substr(kSectionMark.size());
      while (!header.empty() && (header.back() == '\n' || header.back() == '\r' || header.back() == ' '))
        header.remove_suffix(1);
      name = std::string(header);
    } else {
      text += line;
    }
    begin = next;
  }
  flush();
  return parts;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  camdyn::fuzz::silence_streams();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const camdyn::fuzz::Scratch& scratch = camdyn::fuzz::Scratch::get();
  scratch.clear();
  const Parts parts = split_input(std::string_view(reinterpret_cast<const char*>(data), size), scratch);
  camdyn::StudyRequest request;
  request.config_file = scratch.write("main.json", parts.main).string();
  request.overrides = parts.overrides;
  request.out_dir = (scratch.dir() / "out").string();
  request.jobs = 1;
  request.validate_only = true;
  camdyn::fuzz::expect_camdyn_errors_only([&] { camdyn::run_study(request); });
  return 0;
}
