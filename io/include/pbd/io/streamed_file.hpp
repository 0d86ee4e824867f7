#pragma once
/// \file streamed_file.hpp
/// A text file written as a run goes (`pbd run --stats`, `--breaks`): each record is written as it is made, with
/// one write(), so whatever stops the run (an error, SIGINT, SIGTERM) leaves on disk every record made so far as a
/// complete file. A SIGKILL during a write can cut the last record short; nothing else is lost.
#include <filesystem>
#include <string_view>
#include <utility>

namespace pbd {

class StreamedFile {
 public:
  /// Opens `file` for writing (created, or emptied if it exists) and writes `header`, so that a file that cannot be
  /// written (a folder, a missing folder, a read-only file system, a full device such as /dev/full) is refused here,
  /// before any work. A FIFO is opened without blocking: one that no process reads is an error, not a hang. Throws
  /// pbd::Error naming `file` and the system's reason.
  StreamedFile(std::filesystem::path file, std::string_view header);
  StreamedFile(StreamedFile&& other) noexcept : file_(std::move(other.file_)), fd_(std::exchange(other.fd_, -1)) {}
  StreamedFile& operator=(StreamedFile&&) = delete;
  ~StreamedFile();  ///< closes the file (errors then are not reported: call close())

  /// Appends `records` (whole lines) with one write(). Throws pbd::Error naming the file if it fails.
  void append(std::string_view records);
  /// Closes the file; throws pbd::Error naming it if the system reports a failed write. Idempotent.
  void close();
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  int fd_ = -1;
};

}  // namespace pbd
