// libFuzzer target: the study report reader (parse_report) and `pbd study merge` (merge_reports) on arbitrary bytes.
// The input is one report, or several separated by NUL bytes (a NUL is never JSON): each is read, the first written
// in every form, and all of them merged, as `pbd study merge` does, and the merged report written in every form.
// A pbd::Error is the expected answer to bad input; anything else (a crash, another exception, a sanitizer report,
// a hang, a huge allocation, a report written that its own reader refuses) is a bug.
#include "pbd/error.hpp"
#include "report_reader.hpp"
#include "study_report.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace {

using pbd::cli::Report;

// The JSON, table and CSV forms of `report`; its JSON must read back.
void write(const Report& report, const std::string& name) {
  const std::string json = pbd::cli::report_json(report).dump(1);
  std::ostringstream text;
  pbd::cli::print_table(text, report);
  pbd::cli::print_csv(text, report);
  (void)pbd::cli::parse_report(json, name + " (written)");  // not caught: what pbd writes, it reads
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> texts;
  for (std::size_t begin = 0; begin <= input.size() && texts.size() < 4;) {
    const std::size_t end = std::min(input.find('\0', begin), input.size());
    texts.push_back(input.substr(begin, end - begin));
    begin = end + 1;
  }
  std::vector<Report> parts;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < texts.size(); ++i) {
    names.push_back("part" + std::to_string(i + 1) + ".json");
    try {
      parts.push_back(pbd::cli::parse_report(texts[i], names.back()));
    } catch (const pbd::Error&) {
      return 0;
    }
  }
  write(parts.front(), names.front());
  Report merged;
  try {
    // Odd sizes allow mixed machines, so that both paths of the machine check are reached.
    merged = pbd::cli::merge_reports(parts, names, {size % 2 == 1});
  } catch (const pbd::Error&) {
    return 0;
  }
  write(merged, "merged.json");
  return 0;
}
