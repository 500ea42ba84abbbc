#include "io/hex_doubles.h"

#include <bit>

namespace camdyn {

namespace {

constexpr char kHexDigits[] = "0123456789abcdef";

}  // namespace

std::string doubles_to_hex(const std::vector<double>& values) {
  std::string text(16 * values.size(), '0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint64_t bits = std::bit_cast<std::uint64_t>(values[i]);
    for (int d = 15; d >= 0; --d, bits >>= 4) text[16 * i + static_cast<std::size_t>(d)] = kHexDigits[bits & 0xf];
  }
  return text;
}

std::optional<std::vector<double>> doubles_from_hex(std::string_view text, std::size_t count) {
  if (text.size() != 16 * count) return std::nullopt;
  std::vector<double> values(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint64_t bits = 0;
    for (std::size_t d = 0; d < 16; ++d) {
      const char c = text[16 * i + d];
      const int v = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
      if (v < 0) return std::nullopt;
      bits = (bits << 4) | static_cast<std::uint64_t>(v);
    }
    values[i] = std::bit_cast<double>(bits);
  }
  return values;
}

std::vector<std::uint64_t> double_bits(const std::vector<double>& values) {
  std::vector<std::uint64_t> bits(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) bits[i] = std::bit_cast<std::uint64_t>(values[i]);
  return bits;
}

}  // namespace camdyn
