#include "json_reader.hpp"

#include "pbd/detail/message.hpp"

#include <algorithm>
#include <cmath>
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

// Appends `c`, control characters as \xNN.
void append_printable(std::string& out, char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u < 0x20 || u == 0x7f) {
    const char* hex = "0123456789abcdef";
    out += "\\x";
    out += hex[u >> 4];
    out += hex[u & 15];
  } else {
    out += c;
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

  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
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
    what = head(what, 240, cut) + (cut ? "..." : "");
    throw Error(message(file_, ": ", where, what));
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
  const std::string& file_;
  std::vector<json*> open_;        // the arrays and objects being read, outermost first
  std::vector<std::string> path_;  // per open one, the token of the element being read in it
  json* element_ = nullptr;        // the object member whose key was just read
};

}  // namespace

nlohmann::json parse_json(const std::string& text, const std::string& file) {
  nlohmann::json root;
  StrictDom dom(root, text, file);
  try {
    nlohmann::json::sax_parse(text, &dom, nlohmann::json::input_format_t::json, /*strict=*/true);
  } catch (const nlohmann::json::exception& e) {  // parse_error reports every syntax error; this is a safety net
    throw Error(message(file, ": ", e.what()));
  }
  return root;
}

std::string quoted(const std::string& s) {
  bool cut = false;
  std::string out = "\"";
  for (char c : head(s, 64, cut)) {
    if (c == '"' || c == '\\') out += '\\';
    append_printable(out, c);
  }
  return out + (cut ? "...\"" : "\"");
}

std::string pointer_token(const std::string& key) {
  bool cut = false;
  std::string out;
  for (char c : head(key, 64, cut)) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else append_printable(out, c);
  }
  return out + (cut ? "..." : "");
}

std::string describe(const nlohmann::json& v) {
  if (v.is_string()) return quoted(v.get<std::string>());
  if (v.is_array() || v.is_object()) return std::string("an ") + v.type_name();
  return v.dump();
}

void json_fail(const std::string& file, const std::string& path, const std::string& what) {
  throw Error(message(file, ": ", path.empty() ? "/" : path, ": ", what));
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
  return v.get<std::string>();
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
