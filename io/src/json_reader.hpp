#pragma once
// Strict reading of a JSON object: typed, range-checked getters whose errors name the file and the key path
// (JSON Pointer), and a final check that rejects any key nobody asked for. Private to pbd::io.
#include "pbd/error.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>
#include <string>
#include <vector>

namespace pbd::detail {

/// Parses JSON text strictly: a syntax error, a non-finite number (1e400), a key given twice in one object or nesting
/// deeper than kMaxJsonDepth is a pbd::Error naming `file` and the line and column, or the key (JSON Pointer).
nlohmann::json parse_json(const std::string& text, const std::string& file);
inline constexpr std::size_t kMaxJsonDepth = 64;

/// `s` as valid UTF-8 for a message: a byte of no valid UTF-8 sequence and a control character as \xNN. Every
/// text a message quotes from input (file names included) goes through it.
std::string printable(std::string_view s);
/// The byte offset and code point of the first character of `s` that a scene's string may not hold: a control
/// character (C0, DEL, C1), a zero-width or bidirectional format character (U+200B-U+200F, U+2028-U+202E,
/// U+2066-U+2069, U+FEFF); or a byte of no valid UTF-8 sequence (as its value). Nothing when there is none.
std::optional<std::pair<std::size_t, char32_t>> forbidden_character(std::string_view s);

/// `s` in double quotes for a message: control characters escaped, cut to 64 bytes.
std::string quoted(const std::string& s);
/// `key` as one JSON Pointer token ("~" and "/" escaped as RFC 6901 says), cut to 64 bytes.
std::string pointer_token(const std::string& key);
/// A short description of `v` for a message: scalars as written (strings quoted), containers by type.
std::string describe(const nlohmann::json& v);

class JsonObject {
public:
  /// Wraps `value` found at `path` in `file`; throws unless it is an object.
  JsonObject(const nlohmann::json& value, std::string file, std::string path);

  bool has(const std::string& key) const;
  double number(const std::string& key, double lo, double hi) const;                  ///< required
  double number(const std::string& key, double lo, double hi, double fallback) const;  ///< optional
  long integer(const std::string& key, long lo, long hi) const;
  long integer(const std::string& key, long lo, long hi, long fallback) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  std::array<double, 3> vec3(const std::string& key) const;
  std::array<double, 3> vec3(const std::string& key, std::array<double, 3> fallback) const;
  JsonObject object(const std::string& key) const;
  /// The value under `key` (required) as it is, for a key that takes more than one type (a number or an object).
  const nlohmann::json& value(const std::string& key) const { return at(key); }
  /// Elements of an array under `key` (required), each with its own path.
  std::vector<std::pair<const nlohmann::json*, std::string>> array(const std::string& key) const;

  /// Throws if the object has a key that no getter asked for (typos are errors, not silently ignored).
  void reject_unknown_keys() const;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;  ///< error at path/key
  const std::string& file() const { return file_; }
  std::string path(const std::string& key) const { return path_ + "/" + pointer_token(key); }

private:
  const nlohmann::json& at(const std::string& key) const;
  const nlohmann::json& value_;
  std::string file_, path_;
  mutable std::vector<std::string> used_;
};

/// Error at an arbitrary path of `file`.
[[noreturn]] void json_fail(const std::string& file, const std::string& path, const std::string& what);
/// Reads a number from `v` (at `path`): finite, within float's range (every scene runs in float and double), and
/// in [lo, hi].
double json_number(const nlohmann::json& v, const std::string& file, const std::string& path, double lo, double hi);
/// Reads an integer from `v` (at `path`) in [lo, hi].
long json_integer(const nlohmann::json& v, const std::string& file, const std::string& path, long lo, long hi);
/// Reads a 3-vector [x, y, z] from `v` (at `path`), each component as json_number reads it.
std::array<double, 3> json_vec3(const nlohmann::json& v, const std::string& file, const std::string& path);

inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace pbd::detail
