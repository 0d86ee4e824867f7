#include "pbd/io/atomic_file.hpp"

#include "pbd/detail/fault_injection.hpp"
#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/stat.h>
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

// Writes `content` straight to `file`, which is not a regular file. O_NONBLOCK: opening a FIFO that no process reads
// fails (ENXIO) instead of waiting for a reader forever; the writes then block as usual.
void write_through(const std::filesystem::path& file, std::string_view content) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0 && errno == ENXIO) fail(file, "cannot open for writing: it is a FIFO that no process reads", ENXIO);
  if (fd < 0) fail(file, "cannot open for writing", errno);
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  const bool written = write_all(fd, content);
  const int error = errno;
  const bool closed = ::close(fd) == 0;
  if (!written) fail(file, "write failed", error);
  if (!closed) fail(file, "write failed", errno);
}

// "<file>.<pid>.<n>.tmp": a name of this process's own next to the file (remove_stale_temporaries reads the pid).
std::string temporary_name(const std::filesystem::path& file) {
  static std::atomic<unsigned> counter{0};
  return detail::message(file.string(), ".", ::getpid(), ".", counter.fetch_add(1, std::memory_order_relaxed), ".tmp");
}

// Gives the unnamed file `fd` (O_TMPFILE) a temporary name; false (errno set) if the system cannot.
bool name_unnamed(int fd, const std::string& temporary) {
  // Through /proc (any user); else AT_EMPTY_PATH (needs CAP_DAC_READ_SEARCH).
  const std::string self = detail::message("/proc/self/fd/", fd);
  if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temporary.c_str(), AT_SYMLINK_FOLLOW) == 0) return true;
  return ::linkat(fd, "", AT_FDCWD, temporary.c_str(), AT_EMPTY_PATH) == 0;
}

// The tests' fault point of frame writing (pbd/detail/fault_injection.hpp), with the content written and not yet
// named: an injected failure closes `fd` and removes `temporary` (if named), as a failed write does.
void fault_after_writing(int fd, const char* temporary) {
  try {
    detail::fault_point(detail::FaultPhase::frame_write);
  } catch (...) {
    ::close(fd);
    if (temporary) ::unlink(temporary);
    throw;
  }
}

// Renames `temporary` over `file`, removing the temporary if that fails.
void replace(const std::filesystem::path& file, const std::string& temporary) {
  if (::rename(temporary.c_str(), file.c_str()) != 0) {
    const int rename_error = errno;
    ::unlink(temporary.c_str());
    fail(file, "cannot replace it with the new content", rename_error);
  }
}

// The content written as a named temporary, then renamed over `file` (where O_TMPFILE is not to be had).
void write_named(const std::filesystem::path& file, std::string_view content) {
  const std::string temporary = temporary_name(file);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) fail(file, "cannot open for writing", errno);
  const bool written = write_all(fd, content);
  const int error = errno;
  fault_after_writing(fd, temporary.c_str());
  const bool closed = ::close(fd) == 0;
  const int close_error = errno;
  if (!written || !closed) {
    ::unlink(temporary.c_str());
    fail(file, "write failed", written ? close_error : error);
  }
  replace(file, temporary);
}

// The content written as an unnamed file in `file`'s folder, so that a process killed while writing leaves nothing;
// named only once complete. False if the file system has no O_TMPFILE (or the file cannot be named): the caller
// writes it under a name instead.
bool write_unnamed(const std::filesystem::path& file, std::string_view content) {
  const std::filesystem::path folder = file.has_parent_path() ? file.parent_path() : ".";
  const int fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
  if (fd < 0) {
    if (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL) return false;  // no O_TMPFILE here
    fail(file, "cannot open for writing", errno);
  }
  if (!write_all(fd, content)) {
    const int error = errno;
    ::close(fd);
    fail(file, "write failed", error);
  }
  fault_after_writing(fd, nullptr);
  const std::string temporary = temporary_name(file);
  if (!name_unnamed(fd, temporary)) {
    ::close(fd);
    return false;
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    fail(file, "write failed", error);
  }
  replace(file, temporary);
  return true;
}

// The pid in a temporary's name "<name>.<pid>.<n>.tmp", or 0 if `name` is not one.
pid_t pid_of_temporary(const std::string& name) {
  if (name.size() < 4 || name.compare(name.size() - 4, 4, ".tmp") != 0) return 0;
  const std::size_t n_dot = name.rfind('.', name.size() - 5);
  if (n_dot == std::string::npos || n_dot == 0) return 0;
  const std::size_t pid_dot = name.rfind('.', n_dot - 1);
  if (pid_dot == std::string::npos) return 0;
  auto digits = [&](std::size_t from, std::size_t to) {
    return to > from && name.find_first_not_of("0123456789", from) >= to;
  };
  if (!digits(pid_dot + 1, n_dot) || !digits(n_dot + 1, name.size() - 4) || n_dot - pid_dot > 10) return 0;
  return pid_t(std::stol(name.substr(pid_dot + 1, n_dot - pid_dot - 1)));
}

}  // namespace

void write_file_atomically(const std::filesystem::path& file, std::string_view content, NonRegularFile non_regular) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);  // stat: never opens it
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    if (std::filesystem::is_directory(status)) fail(file, "cannot write: it is a folder", EISDIR);
    if (non_regular == NonRegularFile::refuse)
      throw Error(detail::message(file.string(), ": cannot write: it is not a regular file (a FIFO, a device or a",
                                  " socket has taken its name); remove it"));
    write_through(file, content);
    return;
  }
  if (!write_unnamed(file, content)) write_named(file, content);
}

std::size_t remove_stale_temporaries(const std::filesystem::path& dir, std::string_view prefix) {
  std::size_t removed = 0;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const pid_t pid = pid_of_temporary(name);
    if (pid <= 0 || pid == ::getpid()) continue;
    std::error_code type_ec;
    if (!it->is_regular_file(type_ec) || it->is_symlink(type_ec)) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // its process still runs (or is another user's)
    if (::unlink(it->path().c_str()) == 0) ++removed;
  }
  return removed;
}

}  // namespace pbd
