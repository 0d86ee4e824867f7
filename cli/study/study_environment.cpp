#include "study_environment.hpp"

#include "load_monitor.hpp"

#include <pbd/version.hpp>

#include <unistd.h>

#include <ctime>
#include <fstream>
#include <thread>

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

std::string host_name() {
  char name[256] = {};
  return gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string();
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

nlohmann::json study_context(const nlohmann::json& env) {
  return {{"pbd_version", pbd::version},
          {"compiler", or_null(compiler())},
          {"flags", PBD_CXX_FLAGS},
          {"build_type", or_null(PBD_BUILD_TYPE)},
          {"cpu", env["machine"]["cpu"]},
          {"cores", env["machine"]["nproc"]},
          {"host", env["machine"]["host"]},
          {"date", env["date"]},
          {"commit", env["git_commit"]},
          {"loadavg_start", or_null(load_average())}};
}

nlohmann::json study_environment(const std::string& commit) {
  return {{"pbd_version", pbd::version},
          {"command", or_null(command_line())},
          {"date", utc_now()},
          {"machine",
           {{"nproc", std::thread::hardware_concurrency()},
            {"cpu", or_null(cpu_model())},
            {"host", or_null(host_name())},
            {"load_average_at_start", or_null(load_average())}}},
          {"git_commit", commit.empty() ? "unknown" : commit}};
}

}  // namespace pbd::cli
