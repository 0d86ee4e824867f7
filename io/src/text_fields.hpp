#pragma once
// Fields of text mesh files (Gmsh ASCII, TetGen): splitting a line and reading its numbers (private to pbd::io).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pbd::detail {

/// Splits `line` at spaces, tabs and carriage returns into `fields` (cleared first; the views point into `line`).
void split_fields(std::string_view line, std::vector<std::string_view>& fields);

/// The integer `field` writes in decimal ([+-] digits, in int64 range), or nothing.
std::optional<std::int64_t> integer_field(std::string_view field);

/// The number `field` writes ([+-] digits [. digits] [(e|E) [+-] digits], or with digits after the point only, or
/// inf or nan), or nothing. A number beyond the double range reads as an infinity of its sign, so that the caller's
/// finiteness check names it.
std::optional<double> number_field(std::string_view field);

/// Line and column (both from 1) of a byte of a text.
struct TextPosition {
  std::size_t line = 0, column = 0;
};
/// Where the first NUL byte of `text` is, or nothing. A text file holds none: a reader that took one for the end of
/// the text would silently drop what follows it, so every text reader refuses one, naming this position.
std::optional<TextPosition> nul_byte(std::string_view text);

/// `field` as a message shows it: at most 40 characters, bytes that are not printable ASCII as '?'.
std::string shown(std::string_view field);

}  // namespace pbd::detail
