// Text from the user's files (config keys and values, CSV headers, file
// names) is data: before it reaches a terminal in a message it is made
// printable, so that an escape sequence in an input cannot clear the screen,
// retitle the window or hide the rest of the message (docs/config.md, "Data files").
#pragma once

#include <string>
#include <string_view>

namespace camdyn {

/// `text` with every control character written as an escape: C0 (U+0000–U+001F)
/// but newline and tab as `\xNN`, DEL as `\x7f`, C1 (U+0080–U+009F) and the
/// bidirectional overrides and isolates (U+202A–U+202E, U+2066–U+2069) as
/// `\uNNNN`, and bytes that are not UTF-8 as `\xNN`. Printable text, UTF-8
/// included, is kept; text without control characters is returned unchanged, so
/// the function is idempotent.
std::string printable_text(std::string_view text);

}  // namespace camdyn
