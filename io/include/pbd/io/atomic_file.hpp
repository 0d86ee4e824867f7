#pragma once
/// \file atomic_file.hpp
/// Files written whole or not at all: every file pbd writes (frames, series, reports, CSV) goes through here.
#include <cstddef>
#include <filesystem>
#include <string_view>

namespace pbd {

/// What write_file_atomically does where `file` exists and is not a regular file.
enum class NonRegularFile {
  write_through,  ///< write the bytes straight to it (/dev/stdout, a pipe, a device the user named)
  refuse,         ///< throw pbd::Error naming it, without opening it (a name pbd made up: a frame, a .pvd)
};

/// Writes `content` to `file`. A regular file (or a new one) is written as an unnamed file in the same folder
/// (O_TMPFILE, where the file system has it; else under a temporary name "<file>.<pid>.<n>.tmp"), given a temporary
/// name only once every byte is written, and renamed over `file`: a failure (a full disk, a file size limit) leaves
/// `file` as it was and no temporary behind, and a process killed while writing (SIGKILL) leaves at most a complete
/// temporary, which remove_stale_temporaries removes. Where `file` exists and is not a regular file, `non_regular`
/// decides; a FIFO is opened without blocking, so one that no process reads is an error, not a hang. Throws
/// pbd::Error naming `file` and the system's reason.
void write_file_atomically(const std::filesystem::path& file, std::string_view content,
                           NonRegularFile non_regular = NonRegularFile::write_through);

/// Removes from folder `dir` the temporaries write_file_atomically left there ("<name>.<pid>.<n>.tmp", a regular
/// file) whose name starts with `prefix` and whose process no longer runs (a run killed by SIGKILL). Returns how
/// many it removed; a folder that cannot be read removes none.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir, std::string_view prefix);

}  // namespace pbd
