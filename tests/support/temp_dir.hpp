#pragma once
// A scratch directory of the running test: its own name and the process id, so tests that CTest runs in parallel
// never share a file. Removed with everything in it when the object goes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace pbd::test {

class TempDir {
public:
  explicit TempDir(const std::string& prefix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "none";
    path_ = std::filesystem::temp_directory_path() / (prefix + "_" + test + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }  ///< the directory
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }  ///< a file in it

private:
  std::filesystem::path path_;
};

}  // namespace pbd::test
