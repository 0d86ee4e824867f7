#pragma once
// A whole file read into memory with the refusals every mesh reader makes (private to pbd::io).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string_view>
#include <utility>

namespace pbd::detail {

/// The bytes of a file, held in a buffer nothing filled first (a file of hundreds of MB is not zeroed, then read).
class FileBytes {
public:
  FileBytes(std::unique_ptr<char[]> data, std::size_t size) : data_(std::move(data)), size_(size) {}
  std::string_view view() const { return {data_.get(), size_}; }

private:
  std::unique_ptr<char[]> data_;
  std::size_t size_;
};

/// Reads `file` whole. Throws pbd::Error naming it (and `kind`, e.g. "Gmsh file", in what cannot be read) when it is
/// missing, not a regular file (checked before it is opened, so that a FIFO or a device never blocks the read),
/// empty, larger than `max_bytes` (refused from its size, before anything is read) or unreadable.
FileBytes read_file_bytes(const std::filesystem::path& file, const char* kind, std::uintmax_t max_bytes);

}  // namespace pbd::detail
