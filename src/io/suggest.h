// Closest-key suggestions for error messages ("did you mean 'rpm'?"), so a
// typo in a config key or an enumerated value is caught with a useful hint.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace camdyn {

/// Damerau–Levenshtein distance in its optimal-string-alignment form: the
/// number of insertions, deletions, substitutions and transpositions of two
/// adjacent characters that turn `a` into `b`. Case-sensitive.
std::size_t edit_distance(std::string_view a, std::string_view b);

/// Shortest word taken for a partial name (closest_match).
inline constexpr std::size_t kMinPartialLength = 3;

/// The candidate closest to `word` (case-insensitive), if it is close enough
/// to be a plausible typo: distance ≤ 1 for words of up to 3 characters, ≤ 2 up
/// to 6, ≤ 3 beyond. Ties go to the earlier candidate. Failing that, a partial
/// name of at least kMinPartialLength characters: the shortest candidate that
/// starts with `word`.
std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" for the closest match, or "" when there is none.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace camdyn
