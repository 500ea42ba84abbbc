// Doubles written exactly as text: each double as the 16 lower-case hex
// digits of its IEEE-754 bits, most significant first, concatenated. Used by
// the journals (identify, optimize) so that a replayed value is the same to
// the bit, and quick to read back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace camdyn {

/// `values` as 16 hex digits each.
std::string doubles_to_hex(const std::vector<double>& values);

/// The inverse of doubles_to_hex; nothing when `text` is not `count` doubles of hex.
std::optional<std::vector<double>> doubles_from_hex(std::string_view text, std::size_t count);

/// The bits of each double: a map key that tells apart what == would not (-0.0, NaN payloads).
std::vector<std::uint64_t> double_bits(const std::vector<double>& values);

}  // namespace camdyn
