#include "file_bytes.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <fstream>
#include <system_error>

namespace pbd::detail {

FileBytes read_file_bytes(const std::filesystem::path& file, const char* kind, std::uintmax_t max_bytes) {
  const std::string name = file.string();
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status))
    throw Error(message(name, ": cannot read the ", kind, " (", ec ? ec.message() : "no such file", ")"));
  if (!std::filesystem::is_regular_file(status))
    throw Error(message(name, ": cannot read the ", kind, " (not a regular file)"));
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(message(name, ": cannot read the ", kind, " (", ec.message(), ")"));
  if (size == 0) throw Error(name + ": the file is empty (0 bytes)");
  if (size > max_bytes)
    throw Error(message(name, ": the file is ", size, " bytes, more than the ", max_bytes, " a ", kind, " may have"));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(message(name, ": cannot open the ", kind));
  std::unique_ptr<char[]> data(new char[std::size_t(size)]);
  in.read(data.get(), std::streamsize(size));
  if (in.bad()) throw Error(message(name, ": cannot read the ", kind, " (read error)"));
  // A file that shrank since its size was taken is read as far as it goes.
  const std::size_t read = std::size_t(in.gcount());
  if (read == 0) throw Error(name + ": the file is empty (0 bytes)");
  return FileBytes(std::move(data), read);
}

}  // namespace pbd::detail
