#pragma once
// How busy the machine is while `pbd study` measures: the number of other processes' runnable threads, sampled
// (the system's running count from /proc/stat minus this process's own running threads). A load average would
// count the study itself and the build that ran just before it; the report still records it (load_average()), as
// Google Benchmark's context does.
#include <string>
#include <vector>

namespace pbd::cli {

/// Samples of the other processes' runnable threads.
class LoadMonitor {
public:
  /// One sample now: runnable threads of other processes (0 when /proc cannot be read).
  double sample();
  /// Mean of `count` samples taken `interval_ms` apart (for the load before the study starts).
  double settle(int count, int interval_ms);
  /// Mean and maximum of every sample taken since construction (excluding settle()'s).
  double mean() const;
  double max() const;
  /// Mean of the samples taken since `from` (an index returned by count()).
  double mean_since(std::size_t from) const;
  std::size_t count() const { return samples_.size(); }  ///< samples taken so far

private:
  std::vector<double> samples_;
};

/// The 1-, 5- and 15-minute load averages ("a b c"), or "" when /proc/loadavg cannot be read.
std::string load_average();

/// The cut above which a point's timing is marked busy: other processes held at least half a core on average.
constexpr double kBusyLoad = 0.5;
/// The coefficient of variation above which a point's timing is marked busy.
constexpr double kBusyCv = 0.10;

}  // namespace pbd::cli
