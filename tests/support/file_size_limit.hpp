#pragma once
// A full disk, simulated: while a FileSizeLimit lives, no file of this process may grow past `bytes` (RLIMIT_FSIZE)
// and a write past it fails with EFBIG instead of raising SIGXFSZ. Restores both on destruction.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <csignal>
#include <cstddef>

namespace pbd::test {

class FileSizeLimit {
public:
  explicit FileSizeLimit(std::size_t bytes) : previous_(std::signal(SIGXFSZ, SIG_IGN)) {
    EXPECT_EQ(getrlimit(RLIMIT_FSIZE, &old_), 0);
    rlimit small = old_;
    small.rlim_cur = bytes;
    EXPECT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, previous_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

private:
  rlimit old_{};
  void (*previous_)(int);
};

}  // namespace pbd::test
