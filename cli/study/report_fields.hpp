#pragma once
// One JSON object of a study report, read field by field: each getter checks that its key is there, of its type and
// in its range, and otherwise throws pbd::Error "<file>: <key path>: <what is wrong>" (the key path as
// records[3].threads), so that nothing read from a file reaches the report unchecked.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pbd::cli {

class ReportFields {
public:
  /// The object `value` found at `path` ("" for the document) of `file`; throws unless it is an object.
  ReportFields(const nlohmann::json& value, const std::string& file, std::string path);

  bool has(const std::string& key) const;
  /// An integer in [lo, hi] (a number with a fraction, or beyond the range, is refused).
  long long integer(const std::string& key, long long lo, long long hi) const;
  /// A finite number in [lo, hi].
  double number(const std::string& key, double lo, double hi) const;
  /// null, or a finite number in [lo, hi].
  std::optional<double> number_or_null(const std::string& key, double lo, double hi) const;
  /// An error in its unit: a finite number ≥ 0, or null for one that diverged (infinity).
  double error(const std::string& key) const;
  bool boolean(const std::string& key) const;
  std::optional<bool> boolean_or_null(const std::string& key) const;
  /// A name: a string, not empty, with no control character (it becomes a line of the table and a CSV field).
  std::string name(const std::string& key) const;
  /// null (""), or a name.
  std::string name_or_null(const std::string& key) const;
  /// A name from `valid`.
  std::string one_of(const std::string& key, const std::vector<std::string>& valid) const;
  /// An array of names.
  std::vector<std::string> names(const std::string& key) const;
  /// An array of `min_size` or more finite numbers in [lo, hi].
  std::vector<double> numbers(const std::string& key, double lo, double hi, std::size_t min_size) const;
  /// An array of `min_size` or more integers in [lo, hi].
  std::vector<long long> integers(const std::string& key, long long lo, long long hi, std::size_t min_size) const;
  /// The object under `key`.
  ReportFields object(const std::string& key) const;
  /// The objects of the array under `key`, each with its path (key[i]).
  std::vector<ReportFields> objects(const std::string& key) const;
  /// The value under `key` as it is (checked to be there).
  const nlohmann::json& value(const std::string& key) const;

  /// Throws "<file>: <path of key>: <what>".
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  /// The key path of `key` in this object (records[3].threads).
  std::string path(const std::string& key) const;
  const std::string& file() const { return *file_; }

private:
  const nlohmann::json* value_;
  const std::string* file_;
  std::string path_;
};

/// A short description of a value for a message: scalars as written (cut to 40 bytes), containers by their type.
std::string describe_value(const nlohmann::json& v);

}  // namespace pbd::cli
