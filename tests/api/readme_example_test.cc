// The README's "Use from C++" section quotes examples/cpp verbatim, and the
// CTest package.install_and_consume builds and runs exactly those files
// against an installed camdyn: so the README's example is one CI runs.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const std::string kRoot = CAMDYN_SOURCE_DIR;

TEST(ReadmeExample, UseFromCppQuotesTheExampleProgramVerbatim) {
  const std::string readme = read_text(kRoot + "/README.md");
  ASSERT_NE(readme.find("## Use from C++"), std::string::npos);
  for (const auto& [file, fence] :
       {std::pair{"/examples/cpp/main.cpp", "```cpp\n"}, std::pair{"/examples/cpp/CMakeLists.txt", "```cmake\n"}}) {
    const std::string text = read_text(kRoot + file);
    ASSERT_FALSE(text.empty()) << file;
    EXPECT_NE(readme.find(std::string(fence) + text + "```\n"), std::string::npos) << file << " is not quoted verbatim";
  }
}

}  // namespace
