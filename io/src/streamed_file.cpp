#include "pbd/io/streamed_file.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <system_error>
#include <unistd.h>

namespace pbd {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const char* what, int error) {
  throw Error(detail::message(file.string(), ": ", what, " (", std::strerror(error), ")"));
}

}  // namespace

StreamedFile::StreamedFile(std::filesystem::path file, std::string_view header) : file_(std::move(file)) {
  std::error_code ec;
  if (std::filesystem::is_directory(file_, ec)) fail(file_, "cannot write: it is a folder", EISDIR);
  // O_NONBLOCK for the open only: a FIFO without a reader fails (ENXIO) instead of blocking until one comes.
  fd_ = ::open(file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NONBLOCK | O_CLOEXEC, 0666);
  if (fd_ < 0 && errno == ENXIO) fail(file_, "cannot open for writing: it is a FIFO that no process reads", ENXIO);
  if (fd_ < 0) fail(file_, "cannot open for writing", errno);
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
  try {
    append(header);
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

StreamedFile::~StreamedFile() {
  if (fd_ >= 0) ::close(fd_);
}

void StreamedFile::append(std::string_view records) {
  if (fd_ < 0) throw Error(detail::message(file_.string(), ": written after it was closed"));
  while (!records.empty()) {
    const ssize_t n = ::write(fd_, records.data(), records.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(file_, "write failed", errno);
    records.remove_prefix(std::size_t(n));
  }
}

void StreamedFile::close() {
  if (fd_ < 0) return;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(file_, "write failed", errno);
}

}  // namespace pbd
