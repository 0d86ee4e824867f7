#include "pbd/io/atomic_file.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <system_error>
#include <unistd.h>

namespace pbd {
namespace {

// Writes every byte to `fd`; false (errno set) on the first failed write.
bool write_all(int fd, std::string_view content) {
  while (!content.empty()) {
    const ssize_t n = ::write(fd, content.data(), content.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    content.remove_prefix(std::size_t(n));
  }
  return true;
}

[[noreturn]] void fail(const std::filesystem::path& file, const char* what, int error) {
  throw Error(detail::message(file.string(), ": ", what, " (", std::strerror(error), ")"));
}

}  // namespace

void write_file_atomically(const std::filesystem::path& file, std::string_view content) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    if (std::filesystem::is_directory(status)) fail(file, "cannot write: it is a folder", EISDIR);
    const int fd = ::open(file.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) fail(file, "cannot open for writing", errno);
    const bool written = write_all(fd, content);
    const int error = errno;
    const bool closed = ::close(fd) == 0;
    if (!written) fail(file, "write failed", error);
    if (!closed) fail(file, "write failed", errno);
    return;
  }
  // A name of our own next to the file: pid and a counter, created exclusively.
  static std::atomic<unsigned> counter{0};
  const std::string temporary =
      detail::message(file.string(), ".", ::getpid(), ".", counter.fetch_add(1, std::memory_order_relaxed), ".tmp");
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) fail(file, "cannot open for writing", errno);
  const bool written = write_all(fd, content);
  const int error = errno;
  const bool closed = ::close(fd) == 0;
  const int close_error = errno;
  if (!written || !closed) {
    ::unlink(temporary.c_str());
    fail(file, "write failed", written ? close_error : error);
  }
  if (::rename(temporary.c_str(), file.c_str()) != 0) {
    const int rename_error = errno;
    ::unlink(temporary.c_str());
    fail(file, "cannot replace it with the new content", rename_error);
  }
}

}  // namespace pbd
