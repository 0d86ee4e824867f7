#include "report_fields.hpp"

#include "pbd/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pbd::cli {
namespace {

using json = nlohmann::json;

std::string number_text(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

bool has_control_character(const std::string& s) {
  return std::any_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f;
  });
}

// Whether `v` is an integer in [lo, hi] (an unsigned one beyond long long's range is not).
bool integer_in(const json& v, long long lo, long long hi) {
  if (v.is_number_unsigned()) return v.get<unsigned long long>() <= static_cast<unsigned long long>(hi) &&
                                     static_cast<long long>(v.get<unsigned long long>()) >= lo;
  return v.is_number_integer() && v.get<long long>() >= lo && v.get<long long>() <= hi;
}

std::string range_text(long long lo, long long hi) {
  return "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
}

std::string too_few(std::size_t size, std::size_t min_size) {
  return size == 0 ? "the list is empty" : "the list has " + std::to_string(size) + " items, fewer than " +
                                               std::to_string(min_size);
}

}  // namespace

std::string describe_value(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  std::string text = v.dump(-1, ' ', /*ensure_ascii=*/true, json::error_handler_t::replace);
  if (text.size() > 40) text = text.substr(0, 40) + "...";
  return text;
}

ReportFields::ReportFields(const json& value, const std::string& file, std::string path)
    : value_(&value), file_(&file), path_(std::move(path)) {
  if (!value.is_object())
    throw Error(file + ": " + (path_.empty() ? std::string("(top)") : path_) + ": " + describe_value(value) +
                " is not an object" + (path_.empty() ? " (not a pbd study report)" : ""));
}

std::string ReportFields::path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

void ReportFields::fail(const std::string& key, const std::string& what) const {
  throw Error(*file_ + ": " + path(key) + ": " + what);
}

bool ReportFields::has(const std::string& key) const { return value_->contains(key); }

const json& ReportFields::value(const std::string& key) const {
  const auto it = value_->find(key);
  if (it == value_->end()) fail(key, "missing");
  return *it;
}

long long ReportFields::integer(const std::string& key, long long lo, long long hi) const {
  const json& v = value(key);
  if (!v.is_number_integer()) fail(key, describe_value(v) + " is not an integer");
  if (!integer_in(v, lo, hi)) fail(key, describe_value(v) + " is out of range " + range_text(lo, hi));
  return v.get<long long>();
}

double ReportFields::number(const std::string& key, double lo, double hi) const {
  const json& v = value(key);
  if (!v.is_number()) fail(key, describe_value(v) + " is not a number");
  const double x = v.get<double>();
  if (!std::isfinite(x) || x < lo || x > hi)
    fail(key, describe_value(v) + " is out of range [" + number_text(lo) + ", " + number_text(hi) + "]");
  return x;
}

std::optional<double> ReportFields::number_or_null(const std::string& key, double lo, double hi) const {
  if (value(key).is_null()) return std::nullopt;
  return number(key, lo, hi);
}

double ReportFields::error(const std::string& key) const {
  // JSON numbers cannot be infinite: the report writes a diverged error as null.
  return number_or_null(key, 0.0, std::numeric_limits<double>::max()).value_or(INFINITY);
}

bool ReportFields::boolean(const std::string& key) const {
  const json& v = value(key);
  if (!v.is_boolean()) fail(key, describe_value(v) + " is not true or false");
  return v.get<bool>();
}

std::optional<bool> ReportFields::boolean_or_null(const std::string& key) const {
  if (value(key).is_null()) return std::nullopt;
  return boolean(key);
}

std::string ReportFields::name(const std::string& key) const {
  const json& v = value(key);
  if (!v.is_string()) fail(key, describe_value(v) + " is not a string");
  const std::string s = v.get<std::string>();
  if (s.empty()) fail(key, "is empty");
  if (has_control_character(s)) fail(key, describe_value(v) + " holds a control character");
  return s;
}

std::string ReportFields::name_or_null(const std::string& key) const {
  return value(key).is_null() ? std::string() : name(key);
}

std::string ReportFields::one_of(const std::string& key, const std::vector<std::string>& valid) const {
  const std::string s = name(key);
  if (std::find(valid.begin(), valid.end(), s) != valid.end()) return s;
  std::string list;
  for (const std::string& v : valid) list += (list.empty() ? "" : ", ") + v;
  fail(key, describe_value(value(key)) + " is not one of " + list);
}

std::vector<std::string> ReportFields::names(const std::string& key) const {
  const json& v = value(key);
  if (!v.is_array()) fail(key, describe_value(v) + " is not an array of strings");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const json& item = v[i];
    const std::string where = "[" + std::to_string(i) + "]";
    if (!item.is_string() || item.get<std::string>().empty() || has_control_character(item.get<std::string>()))
      fail(key + where, describe_value(item) + " is not a name (a non-empty string without control characters)");
    out.push_back(item.get<std::string>());
  }
  return out;
}

std::vector<double> ReportFields::numbers(const std::string& key, double lo, double hi, std::size_t min_size) const {
  const json& v = value(key);
  if (!v.is_array()) fail(key, describe_value(v) + " is not an array of numbers");
  if (v.size() < min_size) fail(key, too_few(v.size(), min_size));
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const json& item = v[i];
    if (!item.is_number() || !std::isfinite(item.get<double>()) || item.get<double>() < lo || item.get<double>() > hi)
      fail(key + "[" + std::to_string(i) + "]", describe_value(item) + " is not a number in [" + number_text(lo) +
                                                    ", " + number_text(hi) + "]");
    out.push_back(item.get<double>());
  }
  return out;
}

std::vector<long long> ReportFields::integers(const std::string& key, long long lo, long long hi,
                                              std::size_t min_size) const {
  const json& v = value(key);
  if (!v.is_array()) fail(key, describe_value(v) + " is not an array of integers");
  if (v.size() < min_size) fail(key, too_few(v.size(), min_size));
  std::vector<long long> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const json& item = v[i];
    if (!integer_in(item, lo, hi))
      fail(key + "[" + std::to_string(i) + "]", describe_value(item) + " is not an integer in " + range_text(lo, hi));
    out.push_back(item.get<long long>());
  }
  return out;
}

ReportFields ReportFields::object(const std::string& key) const { return ReportFields(value(key), *file_, path(key)); }

std::vector<ReportFields> ReportFields::objects(const std::string& key) const {
  const json& v = value(key);
  if (!v.is_array()) fail(key, describe_value(v) + " is not an array of objects");
  std::vector<ReportFields> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out.emplace_back(v[i], *file_, path(key) + "[" + std::to_string(i) + "]");
  return out;
}

}  // namespace pbd::cli
