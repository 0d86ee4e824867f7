#include "json_file.hpp"

#include "pbd/error.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <set>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

// Closes a file descriptor on every path out.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::string system_error(int error) { return std::strerror(error); }

// "line L, column C" of byte `at` of `text` (both 1-based).
std::string line_and_column(const std::string& text, std::size_t at) {
  at = std::min(at, text.size());
  const auto begin = text.begin(), end = begin + std::ptrdiff_t(at);
  const std::size_t line = 1 + std::size_t(std::count(begin, end, '\n'));
  const std::size_t line_start = text.rfind('\n', at == 0 ? 0 : at - 1);
  const std::size_t column = line_start == std::string::npos || at == 0 ? at + 1 : at - line_start;
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// A SAX pass over the text that builds nothing: it follows the key path, so that a key given twice in one object or
// nesting deeper than kMaxJsonFileDepth is refused by its path before any value is built (nlohmann's DOM parser is
// iterative, but copying, comparing or printing a deep value recurses), and turns a syntax error into a pbd::Error.
class Scan {
public:
  Scan(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  bool null() { return element(), true; }
  bool boolean(bool) { return element(), true; }
  bool number_integer(json::number_integer_t) { return element(), true; }
  bool number_unsigned(json::number_unsigned_t) { return element(), true; }
  bool number_float(json::number_float_t, const json::string_t&) { return element(), true; }
  bool string(json::string_t&) { return element(), true; }
  bool binary(json::binary_t&) { return element(), true; }
  bool start_object(std::size_t) { return open(true), true; }
  bool start_array(std::size_t) { return open(false), true; }
  bool end_object() { return open_.pop_back(), true; }
  bool end_array() { return open_.pop_back(), true; }

  bool key(json::string_t& k) {
    Level& object = open_.back();
    object.key = k;
    if (!object.keys.insert(k).second) fail(path(), "this key is given twice in the same object");
    return true;
  }

  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    std::string what = e.what();
    if (const auto end = what.find("] "); what.rfind("[json.exception.", 0) == 0 && end != std::string::npos)
      what.erase(0, end + 2);
    // nlohmann names the place of a syntax error; a value the lexer read but cannot hold (a number beyond double,
    // "number overflow parsing '1e400'") gets it here.
    if (what.rfind("parse error", 0) != 0) what = line_and_column(text_, position) + ": " + what;
    if (what.size() > 240) what = what.substr(0, 240) + "...";
    throw Error(source_ + ": not JSON (" + what + ")");
  }

private:
  struct Level {
    bool object;                 // an object (else an array)
    std::set<std::string> keys;  // an object's keys read so far
    std::string key;             // an object's key being read
    std::size_t count = 0;       // an array's elements begun so far
  };

  // A value begins: in an array it is the next element.
  void element() {
    if (!open_.empty() && !open_.back().object) ++open_.back().count;
  }
  void open(bool object) {
    element();
    if (open_.size() >= kMaxJsonFileDepth)
      fail(path(), "arrays and objects nested more than " + std::to_string(kMaxJsonFileDepth) + " deep");
    open_.push_back({object, {}, {}, 0});
  }
  // The key path of the value being read: a.b[2].c ("(top)" for the document itself).
  std::string path() const {
    std::string p;
    for (const Level& l : open_)
      p += l.object ? (p.empty() ? "" : ".") + l.key : "[" + std::to_string(l.count == 0 ? 0 : l.count - 1) + "]";
    if (p.size() > 200) p = "..." + p.substr(p.size() - 200);
    return p.empty() ? "(top)" : p;
  }
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error(source_ + ": " + where + ": " + what);
  }

  const std::string& text_;
  const std::string& source_;
  std::vector<Level> open_;
};

}  // namespace

std::string read_text_file(const std::filesystem::path& file, const std::string& kind, std::uintmax_t max_bytes) {
  const std::string name = file.string();
  auto refuse = [&](const std::string& why) { return Error(name + ": cannot read the " + kind + " (" + why + ")"); };
  struct stat status {};
  if (::stat(name.c_str(), &status) != 0) throw refuse(system_error(errno));
  if (!S_ISREG(status.st_mode)) throw refuse("not a regular file");
  // Opened without blocking, and checked again: the path may have been replaced by a FIFO since.
  const Descriptor in{::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (in.fd < 0) throw refuse(system_error(errno));
  if (::fstat(in.fd, &status) != 0) throw refuse(system_error(errno));
  if (!S_ISREG(status.st_mode)) throw refuse("not a regular file");
  const auto too_large = [&](std::uintmax_t size) {
    return Error(name + ": the file is " + std::to_string(size) + " bytes or more, more than the " +
                 std::to_string(max_bytes) + " a " + kind + " may have");
  };
  if (std::uintmax_t(status.st_size) > max_bytes) throw too_large(std::uintmax_t(status.st_size));
  std::string text(std::size_t(status.st_size), '\0');
  std::size_t size = 0;
  for (;;) {  // to its end, which may have moved since fstat
    if (size == text.size()) {
      if (size > max_bytes) throw too_large(size);
      text.resize(std::min<std::uintmax_t>(std::max<std::size_t>(2 * size, 4096), max_bytes + 1));
    }
    const ssize_t got = ::read(in.fd, text.data() + size, text.size() - size);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw refuse(system_error(errno));
    if (got == 0) break;
    size += std::size_t(got);
  }
  if (size > max_bytes) throw too_large(size);
  text.resize(size);
  if (text.empty()) throw Error(name + ": the " + kind + " is empty (0 bytes)");
  return text;
}

json parse_json_text(const std::string& text, const std::string& source) {
  // A NUL byte is never JSON (a string holds it escaped); nlohmann would stop reading at it.
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos)
    throw Error(source + ": not JSON (a NUL byte at " + line_and_column(text, nul) + ")");
  Scan scan(text, source);
  json::sax_parse(text, &scan, json::input_format_t::json, /*strict=*/true);
  return json::parse(text);  // the scan accepted it: nothing is refused here
}

json read_json_file(const std::filesystem::path& file, const std::string& kind, std::uintmax_t max_bytes) {
  return parse_json_text(read_text_file(file, kind, max_bytes), file.string());
}

}  // namespace pbd::cli
