#pragma once
// A study report read back (for `pbd study merge`): the file checked and parsed as json_file.hpp says, then every
// field the report's code reads checked for its type and range (report_fields.hpp), so that a report that is not
// one pbd wrote is refused naming the file and the key, and never reaches the merge half-read.
#include "study_report.hpp"

#include <cstdint>
#include <string>

namespace pbd::cli {

/// The largest report read: a study of thousands of records is a few MB; its JSON takes several times that in memory.
inline constexpr std::uintmax_t kMaxReportBytes = 256u << 20;

/// The report in `file`; throws pbd::Error naming the file and what is wrong (report_from_json).
Report read_report(const std::string& file);

/// The report in `text`, read as if from the file `source`.
Report parse_report(const std::string& text, const std::string& source);

/// The report read back from JSON (schema 3; the references without their in-memory samples), finished (finish()).
/// Throws pbd::Error "<source>: <key path>: <what is wrong>" for a key that is missing, of another type, or out of
/// its range: counts are integers within the study's option ranges (study_record.hpp), times, loads and errors
/// finite and at least 0 (an error may be null: it diverged), names non-empty strings without control characters,
/// lists of rounds not empty.
Report report_from_json(const nlohmann::json& doc, const std::string& source);

}  // namespace pbd::cli
