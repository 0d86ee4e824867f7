#include "json_reader.hpp"

#include "pbd/detail/message.hpp"

#include "text_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace pbd::detail {
namespace {

// `s` cut to at most `max` bytes without splitting a UTF-8 sequence; `cut` says whether anything was dropped.
std::string head(const std::string& s, std::size_t max, bool& cut) {
  std::size_t n = std::min(s.size(), max);
  while (n > 0 && n < s.size() && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
  cut = n < s.size();
  return s.substr(0, n);
}

// Length of the valid UTF-8 sequence at s[i] (1 to 4 bytes; overlong forms and surrogates are not valid), or 0.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto at = [&](std::size_t k) { return i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0u; };
  const unsigned b = at(0);
  if (b < 0x80) return 1;
  const std::size_t n = b >= 0xC2 && b <= 0xDF ? 2 : b >= 0xE0 && b <= 0xEF ? 3 : b >= 0xF0 && b <= 0xF4 ? 4 : 0;
  if (n == 0) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((at(k) & 0xC0) != 0x80) return 0;
  const unsigned b1 = at(1);
  if ((b == 0xE0 && b1 < 0xA0) || (b == 0xED && b1 > 0x9F) || (b == 0xF0 && b1 < 0x90) || (b == 0xF4 && b1 > 0x8F))
    return 0;
  return n;
}

// The code point of the valid sequence of `n` bytes at s[i].
char32_t code_point(std::string_view s, std::size_t i, std::size_t n) {
  const auto u = [&](std::size_t k) { return char32_t(static_cast<unsigned char>(s[i + k])); };
  if (n == 1) return u(0);
  char32_t c = u(0) & (n == 2 ? 0x1F : n == 3 ? 0x0F : 0x07);
  for (std::size_t k = 1; k < n; ++k) c = (c << 6) | (u(k) & 0x3F);
  return c;
}

// A control character (C0, DEL, C1) or a zero-width, line-separating or bidirectional format character: invisible,
// or reordering the text around it.
bool invisible(char32_t c) {
  return c < 0x20 || (c >= 0x7F && c <= 0x9F) || (c >= 0x200B && c <= 0x200F) || (c >= 0x2028 && c <= 0x202E) ||
         (c >= 0x2066 && c <= 0x2069) || c == 0xFEFF;
}

void append_hex(std::string& out, unsigned char u) {
  const char* hex = "0123456789abcdef";
  out += "\\x";
  out += hex[u >> 4];
  out += hex[u & 15];
}

// Appends `s` for a message: valid UTF-8 whatever `s` holds (a byte of no valid sequence as \xNN, so that no reader
// of the message, Python's exception among them, fails to decode it and loses it), an ASCII control character as
// \xNN and any other invisible one as \uNNNN, so that the message shows what is there.
void append_printable(std::string& out, std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_length(s, i);
    const char32_t c = n == 0 ? 0 : code_point(s, i, n);
    if (n == 0 || c < 0x80) {
      if (n == 0 || invisible(c)) append_hex(out, static_cast<unsigned char>(s[i]));
      else out += s[i];
      ++i;
    } else if (invisible(c)) {
      char code[8];
      std::snprintf(code, sizeof code, "\\u%04x", unsigned(c));
      out += code;
      i += n;
    } else {
      out.append(s, i, n);
      i += n;
    }
  }
}

// Builds the value like nlohmann's own DOM parser (json_sax_dom_parser), and also rejects a key given twice in one
// object and nesting deeper than kMaxJsonDepth, naming the key as a JSON Pointer. Pointers to the open arrays and
// objects stay valid: only the innermost one grows.
class StrictDom {
public:
  using json = nlohmann::json;
  StrictDom(json& root, const std::string& text, const std::string& file) : root_(root), text_(text), file_(file) {}

  bool null() { return value(json(nullptr)), true; }
  bool boolean(bool b) { return value(json(b)), true; }
  bool number_integer(json::number_integer_t x) { return value(json(x)), true; }
  bool number_unsigned(json::number_unsigned_t x) { return value(json(x)), true; }
  bool number_float(json::number_float_t x, const json::string_t&) { return value(json(x)), true; }
  bool string(json::string_t& x) { return value(json(std::move(x))), true; }
  bool binary(json::binary_t& x) { return value(json(std::move(x))), true; }
  bool start_object(std::size_t) { return open(json::value_t::object), true; }
  bool start_array(std::size_t) { return open(json::value_t::array), true; }
  bool end_object() { return close(), true; }
  bool end_array() { return close(), true; }

  bool key(json::string_t& k) {
    json& object = *open_.back();
    path_.back() = pointer_token(k);
    if (object.contains(k)) json_fail(file_, pointer(), "this key is given twice in the same object");
    element_ = &object[k];
    return true;
  }

  // nlohmann's lexer takes a NUL byte for the end of the input: an error the lexer met at or after the first one
  // (`position` counts the bytes read, that one included) is that byte, and without any error, what follows it was
  // dropped unread. Either way the NUL byte is refused, naming where it is.
  void refuse_nul(std::size_t position) const {
    if (nul_ == std::string::npos || position <= nul_) return;
    const TextPosition at = *nul_byte(text_);
    throw Error(message(printable(file_), ": parse error at line ", at.line, ", column ", at.column,
                        ": a NUL byte, a control character no JSON text holds (is this a binary file?)"));
  }

  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    refuse_nul(position);
    std::string what = e.what();
    if (const auto end = what.find("] "); what.rfind("[json.exception.", 0) == 0 && end != std::string::npos)
      what.erase(0, end + 2);
    std::string where;  // the key, for a value the lexer read but cannot hold
    if (what.rfind("parse error", 0) != 0) {  // e.g. "number overflow parsing '1e400'": add where it is
      const std::size_t at = std::min(position, text_.size());
      const std::size_t line = 1 + std::size_t(std::count(text_.begin(), text_.begin() + std::ptrdiff_t(at), '\n'));
      const std::size_t line_start = text_.rfind('\n', at == 0 ? 0 : at - 1);
      const std::size_t column = line_start == std::string::npos || at == 0 ? at : at - line_start - 1;
      what = message("parse error at line ", line, ", column ", column, ": ", what);
      if (!open_.empty()) where = reading() + ": ";
    }
    bool cut = false;
    std::string shown;  // nlohmann quotes the bytes it read last as they are: any byte of the file
    append_printable(shown, head(what, 240, cut));
    throw Error(message(printable(file_), ": ", where, shown, cut ? "..." : ""));
  }

private:
  json* value(json&& v) {
    if (open_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    json& parent = *open_.back();
    if (parent.is_array()) {
      path_.back() = std::to_string(parent.size());
      parent.push_back(std::move(v));
      return &parent.back();
    }
    *element_ = std::move(v);
    return element_;
  }
  void open(json::value_t type) {
    json* v = value(json(type));
    if (open_.size() >= kMaxJsonDepth)
      json_fail(file_, pointer(), message("arrays and objects nested more than ", kMaxJsonDepth, " deep"));
    open_.push_back(v);
    path_.emplace_back();
  }
  void close() {
    open_.pop_back();
    path_.pop_back();
  }
  std::string pointer() const {
    std::string p;
    for (const auto& token : path_) p += "/" + token;
    return p;
  }
  // Pointer of the value being read (open_ not empty): the next element of an array, or the value of the key just
  // read in an object.
  std::string reading() const {
    std::string p;
    for (std::size_t i = 0; i + 1 < path_.size(); ++i) p += "/" + path_[i];
    const json& innermost = *open_.back();
    return p + "/" + (innermost.is_array() ? std::to_string(innermost.size()) : path_.back());
  }

  json& root_;
  const std::string& text_;
  const std::size_t nul_ = text_.find('\0');  // the first NUL byte, if any
  const std::string& file_;
  std::vector<json*> open_;        // the arrays and objects being read, outermost first
  std::vector<std::string> path_;  // per open one, the token of the element being read in it
  json* element_ = nullptr;        // the object member whose key was just read
};

}  // namespace

std::string printable(std::string_view s) {
  std::string out;
  append_printable(out, s);
  return out;
}

std::optional<std::pair<std::size_t, char32_t>> forbidden_character(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_length(s, i);
    if (n == 0) return std::pair<std::size_t, char32_t>{i, char32_t(static_cast<unsigned char>(s[i]))};
    if (const char32_t c = code_point(s, i, n); invisible(c)) return std::pair<std::size_t, char32_t>{i, c};
    i += n;
  }
  return std::nullopt;
}

nlohmann::json parse_json(const std::string& text, const std::string& file) {
  nlohmann::json root;
  StrictDom dom(root, text, file);
  try {
    nlohmann::json::sax_parse(text, &dom, nlohmann::json::input_format_t::json, /*strict=*/true);
  } catch (const nlohmann::json::exception& e) {  // parse_error reports every syntax error; this is a safety net
    throw Error(message(printable(file), ": ", printable(e.what())));
  }
  dom.refuse_nul(text.size() + 1);  // a valid text followed by a NUL byte: what follows it was never read
  return root;
}

std::string quoted(const std::string& s) {
  bool cut = false;
  std::string escaped;
  for (char c : head(s, 64, cut)) {
    if (c == '"' || c == '\\') escaped += '\\';
    escaped += c;
  }
  std::string out = "\"";
  append_printable(out, escaped);
  out += cut ? "...\"" : "\"";
  return out;
}

std::string pointer_token(const std::string& key) {
  bool cut = false;
  std::string out;
  for (char c : head(key, 64, cut)) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return printable(out) + (cut ? "..." : "");
}

std::string describe(const nlohmann::json& v) {
  if (v.is_string()) return quoted(v.get<std::string>());
  if (v.is_array() || v.is_object()) return std::string("an ") + v.type_name();
  return v.dump();
}

void json_fail(const std::string& file, const std::string& path, const std::string& what) {
  throw Error(message(printable(file), ": ", path.empty() ? "/" : path, ": ", what));
}

double json_number(const nlohmann::json& v, const std::string& file, const std::string& path, double lo, double hi) {
  if (!v.is_number()) json_fail(file, path, message("expected a number, got ", describe(v)));
  const double x = v.get<double>();
  if (!std::isfinite(x)) json_fail(file, path, "expected a finite number");
  if (std::abs(x) > double(std::numeric_limits<float>::max()))
    json_fail(file, path, message("value ", x, " is beyond the range of float (", std::numeric_limits<float>::max(),
                                  "): a scene must run in float as well as in double"));
  if (x < lo || x > hi) json_fail(file, path, message("value ", x, " is out of range [", lo, ", ", hi, "]"));
  return x;
}

long json_integer(const nlohmann::json& v, const std::string& file, const std::string& path, long lo, long hi) {
  if (!v.is_number_integer()) json_fail(file, path, message("expected an integer, got ", describe(v)));
  if (v.is_number_unsigned() && v.get<unsigned long>() > static_cast<unsigned long>(hi))
    json_fail(file, path, message("value ", v.dump(), " is out of range [", lo, ", ", hi, "]"));
  const long x = v.get<long>();
  if (x < lo || x > hi) json_fail(file, path, message("value ", x, " is out of range [", lo, ", ", hi, "]"));
  return x;
}

std::array<double, 3> json_vec3(const nlohmann::json& v, const std::string& file, const std::string& path) {
  if (!v.is_array() || v.size() != 3) json_fail(file, path, "expected an array of 3 numbers [x, y, z]");
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) out[i] = json_number(v[i], file, path + "/" + std::to_string(i), -kInf, kInf);
  return out;
}

JsonObject::JsonObject(const nlohmann::json& value, std::string file, std::string path)
    : value_(value), file_(std::move(file)), path_(std::move(path)) {
  if (!value_.is_object()) json_fail(file_, path_, message("expected an object, got ", describe(value_)));
}

bool JsonObject::has(const std::string& key) const {
  if (!value_.contains(key)) return false;
  used_.push_back(key);
  return true;
}

const nlohmann::json& JsonObject::at(const std::string& key) const {
  auto it = value_.find(key);
  if (it == value_.end()) fail(key, "required key is missing");
  used_.push_back(key);
  return *it;
}

void JsonObject::fail(const std::string& key, const std::string& what) const { json_fail(file_, path(key), what); }

double JsonObject::number(const std::string& key, double lo, double hi) const {
  return json_number(at(key), file_, path(key), lo, hi);
}
double JsonObject::number(const std::string& key, double lo, double hi, double fallback) const {
  return has(key) ? number(key, lo, hi) : fallback;
}
long JsonObject::integer(const std::string& key, long lo, long hi) const {
  return json_integer(at(key), file_, path(key), lo, hi);
}
long JsonObject::integer(const std::string& key, long lo, long hi, long fallback) const {
  return has(key) ? integer(key, lo, hi) : fallback;
}
bool JsonObject::boolean(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  const auto& v = at(key);
  if (!v.is_boolean()) fail(key, message("expected true or false, got ", describe(v)));
  return v.get<bool>();
}
std::string JsonObject::string(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_string()) fail(key, message("expected a string, got ", describe(v)));
  std::string s = v.get<std::string>();
  // A scene's strings end up in file names, messages and reports: a control character or a bidirectional override
  // there would hide or reorder what a reader sees.
  if (const auto bad = forbidden_character(s)) {
    char code[16];
    std::snprintf(code, sizeof code, "U+%04X", unsigned(bad->second));
    fail(key, message(detail::quoted(s), ": character ", code, " at byte ", bad->first, " is a control or format character "
                      "(invisible, or reordering the text); a scene's strings may not hold one"));
  }
  return s;
}
std::string JsonObject::string(const std::string& key, const std::string& fallback) const {
  return has(key) ? string(key) : fallback;
}
std::array<double, 3> JsonObject::vec3(const std::string& key) const { return json_vec3(at(key), file_, path(key)); }
std::array<double, 3> JsonObject::vec3(const std::string& key, std::array<double, 3> fallback) const {
  return has(key) ? vec3(key) : fallback;
}
JsonObject JsonObject::object(const std::string& key) const { return JsonObject(at(key), file_, path(key)); }

std::vector<std::pair<const nlohmann::json*, std::string>> JsonObject::array(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_array()) fail(key, message("expected an array, got ", describe(v)));
  std::vector<std::pair<const nlohmann::json*, std::string>> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out.emplace_back(&v[i], path(key) + "/" + std::to_string(i));
  return out;
}

void JsonObject::reject_unknown_keys() const {
  for (auto it = value_.begin(); it != value_.end(); ++it)
    if (std::find(used_.begin(), used_.end(), it.key()) == used_.end())
      fail(it.key(), "unknown key (check its spelling and the scene format in docs/scenes.md)");
}

}  // namespace pbd::detail
