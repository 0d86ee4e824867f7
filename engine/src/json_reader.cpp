#include "json_reader.hpp"

#include "message.hpp"

#include <algorithm>
#include <cmath>

namespace pbd::detail {

void json_fail(const std::string& file, const std::string& path, const std::string& what) {
  throw Error(message(file, ": ", path.empty() ? "/" : path, ": ", what));
}

double json_number(const nlohmann::json& v, const std::string& file, const std::string& path, double lo, double hi) {
  if (!v.is_number()) json_fail(file, path, message("expected a number, got ", v.type_name()));
  const double x = v.get<double>();
  if (!std::isfinite(x)) json_fail(file, path, "expected a finite number");
  if (x < lo || x > hi) json_fail(file, path, message("value ", x, " is out of range [", lo, ", ", hi, "]"));
  return x;
}

long json_integer(const nlohmann::json& v, const std::string& file, const std::string& path, long lo, long hi) {
  if (!v.is_number_integer()) json_fail(file, path, message("expected an integer, got ", v.dump()));
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
  if (!value_.is_object()) json_fail(file_, path_, message("expected an object, got ", value_.type_name()));
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
  if (!v.is_boolean()) fail(key, message("expected true or false, got ", v.dump()));
  return v.get<bool>();
}
std::string JsonObject::string(const std::string& key) const {
  const auto& v = at(key);
  if (!v.is_string()) fail(key, message("expected a string, got ", v.type_name()));
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
  if (!v.is_array()) fail(key, message("expected an array, got ", v.type_name()));
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
