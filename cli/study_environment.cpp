#include "study_environment.hpp"

#include "pbd/error.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <thread>

#ifndef PBD_SOURCE_DIR
#define PBD_SOURCE_DIR "."
#endif
#ifndef PBD_BUILD_TYPE
#define PBD_BUILD_TYPE ""
#endif
#ifndef PBD_CXX_FLAGS
#define PBD_CXX_FLAGS ""
#endif

namespace pbd::cli {
namespace {

// Single-quoted for /bin/sh.
std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// First line of a shell command's output, or "" if it fails.
std::string first_line_of(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return "";
  std::array<char, 256> buf{};
  std::string line;
  if (std::fgets(buf.data(), int(buf.size()), pipe)) line = buf.data();
  if (pclose(pipe) != 0) return "";
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return line;
}

nlohmann::json or_null(const std::string& s) { return s.empty() ? nlohmann::json(nullptr) : nlohmann::json(s); }

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      return colon == std::string::npos ? "" : line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  return "";
}


// argv of this process, space-separated (arguments with spaces or quotes single-quoted).
std::string command_line() {
  std::ifstream f("/proc/self/cmdline", std::ios::binary);
  std::string out;
  for (std::string arg; std::getline(f, arg, '\0');) {
    const bool plain = !arg.empty() && arg.find_first_of(" \t'\"\\$") == std::string::npos;
    if (!out.empty()) out += ' ';
    out += plain ? arg : shell_quoted(arg);
  }
  return out;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char s[32];
  std::strftime(s, sizeof s, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return s;
}

std::string compiler() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("gcc ") + __VERSION__;
#else
  return "";
#endif
}

}  // namespace

std::string load_average() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  return f >> a >> b >> c ? a + " " + b + " " + c : "";
}

nlohmann::json study_context() {
  const nlohmann::json env = study_environment();
  return {{"compiler", or_null(compiler())},
          {"flags", PBD_CXX_FLAGS},
          {"build_type", or_null(PBD_BUILD_TYPE)},
          {"cpu", env["machine"]["cpu"]},
          {"cores", env["machine"]["nproc"]},
          {"date", env["date"]},
          {"commit", env["git_commit"]},
          {"loadavg_start", or_null(load_average())}};
}

nlohmann::json study_environment() {
  const std::string git = "git -C " + shell_quoted(PBD_SOURCE_DIR) + " ";
  return {{"command", or_null(command_line())},
          {"date", utc_now()},
          {"machine",
           {{"nproc", std::thread::hardware_concurrency()},
            {"cpu", or_null(cpu_model())},
            {"load_average_at_start", or_null(load_average())}}},
          {"git_commit", or_null(first_line_of(git + "describe --always --dirty --abbrev=12 2>/dev/null"))}};
}

std::filesystem::path plot_script() {
  if (const char* env = std::getenv("PBD_PLOT_SCRIPT"); env && *env) return env;
  return std::filesystem::path(PBD_SOURCE_DIR) / "scripts" / "plot_study.py";
}

void run_plot_script(const std::filesystem::path& json, const std::filesystem::path& dir) {
  const std::filesystem::path script = plot_script();
  if (!std::filesystem::exists(script))
    throw Error("--plots: plot script " + script.string() + " not found (set PBD_PLOT_SCRIPT)");
  const std::string command =
      "/usr/bin/python3 " + shell_quoted(script.string()) + " " + shell_quoted(json.string()) + " " + shell_quoted(dir.string());
  std::fflush(stdout);
  if (std::system(command.c_str()) != 0)
    throw Error("--plots: " + command + " failed (it needs Debian's python3-matplotlib: apt-get install "
                "python3-matplotlib)");
}

}  // namespace pbd::cli
