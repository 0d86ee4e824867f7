#include "data_dir.hpp"

#include <system_error>

namespace pbd::cli {

std::filesystem::path program_file() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe;
}

std::filesystem::path data_dir() {
  const std::filesystem::path exe = program_file();
  if (exe.empty()) return {};
  return exe.parent_path().parent_path() / "share" / "pbd";
}

}  // namespace pbd::cli
