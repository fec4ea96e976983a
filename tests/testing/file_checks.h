#pragma once
// Helpers for tests of files and of input errors: a fresh empty directory per
// test (removed with its files afterwards), a file's contents, the one-line
// InputError message of a call, and a substring matcher.
#include <dirent.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "measure/input_error.h"

namespace surfreg::testing {

class TempDir {
 public:
  TempDir() {
    std::string pattern = ::testing::TempDir() + "/surfreg_test.XXXXXX";
    path_ = mkdtemp(pattern.data()) ? pattern : "";
    EXPECT_FALSE(path_.empty());
  }
  ~TempDir() {
    for (const std::string& name : Files()) ::unlink((path_ + "/" + name).c_str());
    ::rmdir(path_.c_str());
  }
  const std::string& path() const { return path_; }
  std::string File(const std::string& name, const std::string& text) const {
    const std::string file = path_ + "/" + name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }
  std::vector<std::string> Files() const {
    std::vector<std::string> names;
    if (DIR* dir = opendir(path_.c_str())) {
      while (const dirent* entry = readdir(dir)) {
        const std::string name = entry->d_name;
        if (name != "." && name != "..") names.push_back(name);
      }
      closedir(dir);
    }
    return names;
  }

 private:
  std::string path_;
};

inline std::string Contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The InputError message of `f()` ("" if none is thrown).
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    return message;
  }
  return "";
}

// The same, and nothing printed to stderr meanwhile (a library's own
// messages: GDAL's, PROJ's).
template <typename F>
std::string SilentErrorOf(F f) {
  ::testing::internal::CaptureStderr();
  const std::string message = ErrorOf(f);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  return message;
}

inline ::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  const std::string shown = text.size() > 400 ? text.substr(0, 400) + "..." : text;
  return ::testing::AssertionFailure() << "'" << shown << "' does not contain '" << part << "'";
}

}  // namespace surfreg::testing
