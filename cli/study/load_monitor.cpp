#include "load_monitor.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <thread>

namespace pbd::cli {
namespace {

// procs_running of /proc/stat: runnable threads of the whole system, this one included.
int system_running() {
  std::ifstream f("/proc/stat");
  for (std::string key; f >> key;) {
    if (key == "procs_running") {
      int n = 0;
      return f >> n ? n : -1;
    }
    f.ignore(1 << 20, '\n');
  }
  return -1;
}

// This process's threads in state R.
int own_running() {
  int n = 0;
  std::error_code ec;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
    std::ifstream f(task.path() / "stat");
    std::string line;
    if (!std::getline(f, line)) continue;
    const std::size_t paren = line.rfind(')');
    if (paren != std::string::npos && paren + 2 < line.size() && line[paren + 2] == 'R') ++n;
  }
  return std::max(n, 1);  // the sampling thread runs
}

// Other processes' runnable threads now. This process's own count is read before and after the system's and the
// larger is taken: a worker thread that stops spinning between the reads would otherwise count as another process.
double others_running() {
  const int own_before = own_running();
  const int all = system_running();
  const int own_after = own_running();
  return all < 0 ? 0.0 : std::max(0, all - std::max(own_before, own_after));
}

}  // namespace

std::string load_average() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  return f >> a >> b >> c ? a + " " + b + " " + c : "";
}

double LoadMonitor::sample() {
  const double others = others_running();
  samples_.push_back(others);
  return others;
}

double LoadMonitor::settle(int count, int interval_ms) {
  double sum = 0.0;
  for (int k = 0; k < count; ++k) {
    sum += others_running();
    std::this_thread::sleep_for(std::chrono::milliseconds(interval_ms));
  }
  return count > 0 ? sum / count : 0.0;
}

double LoadMonitor::mean() const { return mean_since(0); }

double LoadMonitor::max() const {
  return samples_.empty() ? 0.0 : *std::max_element(samples_.begin(), samples_.end());
}

double LoadMonitor::mean_since(std::size_t from) const {
  if (from >= samples_.size()) return 0.0;
  return std::accumulate(samples_.begin() + long(from), samples_.end(), 0.0) / double(samples_.size() - from);
}

}  // namespace pbd::cli
