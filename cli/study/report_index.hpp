#pragma once
// The items of a report (records, references, derived results) by scene name, so that what is done per scene stays
// linear in the items' count: a merged report holds tens of thousands of records.
#include <map>
#include <string>
#include <vector>

namespace pbd::cli {

/// Indices into a report's vector by name, in the vector's order.
using NameIndex = std::map<std::string, std::vector<std::size_t>>;

/// `items` indexed by `name(item)`.
template <class T, class Name> NameIndex index_by(const std::vector<T>& items, Name name) {
  NameIndex out;
  for (std::size_t i = 0; i < items.size(); ++i) out[name(items[i])].push_back(i);
  return out;
}

/// The indices under `name` (none when it has none).
inline const std::vector<std::size_t>& indices_of(const NameIndex& index, const std::string& name) {
  static const std::vector<std::size_t> none;
  const auto it = index.find(name);
  return it == index.end() ? none : it->second;
}

}  // namespace pbd::cli
