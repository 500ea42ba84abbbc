// The structure-aware config mutator (scene_mutator.h).
#include "scene_mutator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <string_view>
#include <vector>

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

namespace {

using Json = nlohmann::ordered_json;

// Stands for the hostile text in the dumped document; replaced afterwards,
// since NaN, 1e999 or a 10,000-deep array cannot go through a Json value.
constexpr std::string_view kMarker = "\"@@camdyn_fuzz_hostile@@\"";

constexpr const char* kHostileNumbers[] = {"0",
                                           "-0",
                                           "-1",
                                           "1e308",
                                           "-1e308",
                                           "1e999",
                                           "-1e999",
                                           "5e-324",
                                           "-5e-324",
                                           "2.2e-308",
                                           "1e-300",
                                           "1e-12",
                                           "1e19",
                                           "1e100",
                                           "-1e100",
                                           "9007199254740993",
                                           "1e15",
                                           "2147483648",
                                           "-2147483649",
                                           "9223372036854775808",
                                           "18446744073709551616",
                                           "1.5e-6",
                                           "0.5",
                                           "360",
                                           "\"NaN\"",
                                           "\"nan\"",
                                           "\"inf\"",
                                           "\"-inf\"",
                                           "\"Infinity\"",
                                           "null",
                                           "true",
                                           "\"\"",
                                           "[]",
                                           "{}",
                                           "[0]",
                                           "\"x\""};

// Every value in the document, depth first (the root excluded).
void collect(Json& node, std::vector<Json*>& out) {
  if (!node.is_structured()) return;
  for (auto& child : node) {
    out.push_back(&child);
    collect(child, out);
  }
}

std::string nested(std::size_t depth, bool objects) {
  std::string text;
  text.reserve(depth * 6 + 1);
  for (std::size_t i = 0; i < depth; ++i) text += objects ? "{\"a\":" : "[";
  text += "1";
  for (std::size_t i = 0; i < depth; ++i) text += objects ? "}" : "]";
  return text;
}

std::string long_array(std::size_t count, double value) {
  std::string text = "[";
  const std::string item = Json(value).dump();
  for (std::size_t i = 0; i < count; ++i) text += (i ? "," : "") + item;
  return text + "]";
}

// The hostile text for `target` (a value of the document); at most about `room` characters.
std::string hostile_text(const Json& target, std::size_t room, std::minstd_rand& rng) {
  const auto pick = [&rng](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
  switch (pick(8)) {
    case 0:  // deep nesting
      return nested(std::min<std::size_t>(1 + pick(30000), room / 6), pick(2) == 0);
    case 1: {  // a long array of the old value (or of 1)
      const double v = target.is_number() ? target.get<double>() : 1.0;
      return long_array(std::min<std::size_t>(1 + pick(100000), room / 8), v);
    }
    case 2:
    case 3:
      if (target.is_number()) {  // rescaled or negated
        const double scale = std::pow(10.0, static_cast<double>(pick(41)) - 20.0) * (pick(3) == 0 ? -1.0 : 1.0);
        return Json(target.get<double>() * scale).dump();
      }
      [[fallthrough]];
    default:
      return kHostileNumbers[pick(std::size(kHostileNumbers))];
  }
}

// Deepest bracket nesting of JSON text (strings skipped). The mutator leaves
// deeper documents to the byte mutations: nlohmann's dump recurses.
std::size_t nesting(const std::uint8_t* data, std::size_t size) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = static_cast<char>(data[i]);
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

constexpr std::size_t kMaxMutatedDepth = 64;

}  // namespace

namespace camdyn::fuzz {

std::size_t mutate_config_value(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned int seed) {
  std::minstd_rand rng(seed);
  if (nesting(data, size) > kMaxMutatedDepth) return LLVMFuzzerMutate(data, size, max_size);
  Json doc = Json::parse(data, data + size, nullptr, false);
  if (doc.is_discarded() || !doc.is_structured() || rng() % 8 == 0) return LLVMFuzzerMutate(data, size, max_size);
  std::vector<Json*> values;
  collect(doc, values);
  if (values.empty()) return LLVMFuzzerMutate(data, size, max_size);
  // Prefer numbers: they are what the physics reads.
  Json* target = values[rng() % values.size()];
  for (int tries = 0; tries < 4 && !target->is_number(); ++tries) target = values[rng() % values.size()];
  const std::string before = doc.dump();
  const std::size_t room = max_size > before.size() ? max_size - before.size() : 0;
  const std::string text = hostile_text(*target, room, rng);
  *target = std::string(kMarker.substr(1, kMarker.size() - 2));
  std::string out = doc.dump(1);
  const std::size_t at = out.find(kMarker);
  if (at == std::string::npos) return LLVMFuzzerMutate(data, size, max_size);
  out.replace(at, kMarker.size(), text);
  if (out.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, out.data(), out.size());
  return out.size();
}

}  // namespace camdyn::fuzz
