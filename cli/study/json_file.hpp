#pragma once
// The JSON files the study reads (the reports `pbd study merge` joins, a scene file given to `pbd study --scene`):
// refused before they are opened unless they are regular files (a FIFO or a device would block the read), refused
// above a size, and parsed with their nesting bounded (a deeper document overflows the stack when it is copied or
// compared) and no key given twice in one object (the parser would silently keep the last).
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>

namespace pbd::cli {

/// The deepest nesting of arrays and objects accepted, the scene parser's: a report is 5 deep.
inline constexpr std::size_t kMaxJsonFileDepth = 64;

/// The text of `file`; throws pbd::Error naming it and `kind` (e.g. "study report") when it is missing, not a
/// regular file (checked before it is opened, and again on what was opened), empty, larger than `max_bytes` or
/// unreadable.
std::string read_text_file(const std::filesystem::path& file, const std::string& kind, std::uintmax_t max_bytes);

/// `text` parsed as one JSON document; throws pbd::Error naming `source` and, for a syntax error or a NUL byte, the
/// line and column, or for a key given twice or nesting deeper than kMaxJsonFileDepth the key path (a.b[2].c).
nlohmann::json parse_json_text(const std::string& text, const std::string& source);

/// parse_json_text(read_text_file(file, kind, max_bytes), file).
nlohmann::json read_json_file(const std::filesystem::path& file, const std::string& kind, std::uintmax_t max_bytes);

}  // namespace pbd::cli
