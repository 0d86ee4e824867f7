#include "text_fields.hpp"

#include <algorithm>
#include <charconv>
#include <limits>
#include <system_error>

namespace pbd::detail {

void split_fields(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  for (std::size_t pos = 0; pos < line.size();) {
    while (pos < line.size() && space(line[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < line.size() && !space(line[pos])) ++pos;
    if (pos > start) fields.push_back(line.substr(start, pos - start));
  }
}

std::optional<std::int64_t> integer_field(std::string_view field) {
  // from_chars takes no '+'; files written by hand may have one.
  if (field.size() > 1 && field[0] == '+' && field[1] != '-') field.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size()) return std::nullopt;
  return value;
}

std::optional<double> number_field(std::string_view field) {
  if (field.size() > 1 && field[0] == '+' && field[1] != '-') field.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (end != field.data() + field.size() || field.empty()) return std::nullopt;
  if (error == std::errc::result_out_of_range) {
    // Too large, or too small: from_chars leaves the value unset for both; an underflow is as good as 0.
    bool large = true;
    const std::size_t e = field.find_first_of("eE");
    if (e != std::string_view::npos && e + 1 < field.size() && field[e + 1] == '-') large = false;
    const bool negative = field[0] == '-';
    if (!large) return negative ? -0.0 : 0.0;
    return negative ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  }
  if (error != std::errc()) return std::nullopt;
  return value;
}

std::optional<TextPosition> nul_byte(std::string_view text) {
  const std::size_t at = text.find('\0');
  if (at == std::string_view::npos) return std::nullopt;
  const std::string_view before = text.substr(0, at);
  const std::size_t line_start = before.rfind('\n');
  const std::size_t column = line_start == std::string_view::npos ? at + 1 : at - line_start;
  return TextPosition{1 + std::size_t(std::count(before.begin(), before.end(), '\n')), column};
}

std::string shown(std::string_view field) {
  std::string s(field.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return field.size() > 40 ? s + "..." : s;
}

}  // namespace pbd::detail
