#include "fuzz_support.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <streambuf>
#include <system_error>

#include "common/errors.h"

namespace camdyn::fuzz {

namespace {

// A stream buffer that drops everything written to it.
class NullBuffer : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

}  // namespace

Scratch::Scratch() {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/camdyn_fuzz_XXXXXX";
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("fuzz: cannot create a scratch folder");
  dir_ = pattern;
}

Scratch::~Scratch() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);  // best effort at exit
}

Scratch& Scratch::get() {
  static Scratch scratch;
  return scratch;
}

void Scratch::clear() const {
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) std::filesystem::remove_all(entry.path());
}

std::filesystem::path Scratch::write(const std::string& name, std::string_view text) const {
  const std::filesystem::path file = dir_ / name;
  std::ofstream out(file, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw std::runtime_error("fuzz: cannot write " + file.string());
  return file;
}

void silence_streams() {
  static NullBuffer null_buffer;
  std::cout.rdbuf(&null_buffer);
  std::cerr.rdbuf(&null_buffer);
}

void expect_camdyn_errors_only(const std::function<void()>& body) {
  try {
    body();
  } catch (const InputError&) {
  } catch (const NumericalError&) {
  }
}

}  // namespace camdyn::fuzz
