// Text from the user's files is printed as data (common/printable_text.h):
// every control character is written as an escape, printable text is kept.
#include "common/printable_text.h"

#include <gtest/gtest.h>

#include <string>

#include "common/errors.h"

namespace camdyn {
namespace {

TEST(PrintableText, EscapeSequencesBecomeVisibleEscapes) {
  // Clear screen, set the window title (OSC ... BEL), and a C1 CSI in UTF-8 (U+009B).
  EXPECT_EQ(printable_text("a\x1b[2Jb"), "a\\x1b[2Jb");
  EXPECT_EQ(printable_text("\x1b]0;pwned\x07"), "\\x1b]0;pwned\\x07");
  EXPECT_EQ(printable_text("x\xc2\x9b"
                           "2Jy"),
            "x\\u009b2Jy");
  EXPECT_EQ(printable_text(std::string("nul\0cr\rdel\x7f", 11)), "nul\\x00cr\\x0ddel\\x7f");
}

TEST(PrintableText, PrintableTextNewlinesTabsAndUtf8AreKept) {
  const std::string text = "θ = 90°, Δs = 5 mm\n\tnext line — ok";
  EXPECT_EQ(printable_text(text), text);
}

TEST(PrintableText, BytesThatAreNotUtf8AndDirectionOverridesAreEscaped) {
  EXPECT_EQ(printable_text("a\x9b"
                           "b"),
            "a\\x9bb");  // a lone 8-bit C1 byte
  EXPECT_EQ(printable_text("a\xe2\x80\xae"
                           "b"),
            "a\\u202eb");                               // RIGHT-TO-LEFT OVERRIDE
  EXPECT_EQ(printable_text("\xc0\x80"), "\\xc0\\x80");  // an overlong NUL
}

TEST(PrintableText, IsIdempotent) {
  const std::string once = printable_text("k\x1b[31mred\x1b[0m");
  EXPECT_EQ(printable_text(once), once);
}

TEST(PrintableText, InputErrorMessagesCarryTheEscapedForm) {
  const InputError error("a\x1b]0;t\x07.csv", "column \x1b[2J", "bad");
  const std::string what = error.what();
  EXPECT_EQ(what, "a\\x1b]0;t\\x07.csv: column \\x1b[2J: bad");
  EXPECT_EQ(what.find('\x1b'), std::string::npos);
}

}  // namespace
}  // namespace camdyn
