#pragma once
/// \file atomic_file.hpp
/// Files written whole or not at all: every file pbd writes (frames, series, reports, CSV) goes through here.
#include <filesystem>
#include <string_view>

namespace pbd {

/// Writes `content` to `file`. A regular file (or a new one) is written under a temporary name in the same folder and
/// renamed over `file` once every byte is written and closed, so a failure (a full disk, a file size limit) leaves
/// `file` as it was and no temporary behind. Where `file` exists and is not a regular file (/dev/stdout, a pipe, a
/// device) the bytes go straight to it. Throws pbd::Error naming `file` and the system's reason.
void write_file_atomically(const std::filesystem::path& file, std::string_view content);

}  // namespace pbd
