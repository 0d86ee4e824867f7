#pragma once
// Reading back what the VTU frame writer wrote, in tests: a file's text, how often a string occurs in it, the values
// of a named base64 <DataArray> (no checks beyond the byte count: the input is the writer's own output), the cells,
// and the values of one body.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pbd::test {

// The bytes of a file.
inline std::string text_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// How many times `what` occurs in `text`.
inline std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The bytes of base64 text.
inline std::string decode_base64(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : 63;
  };
  std::string out;
  std::uint32_t bits = 0;
  int have = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = bits << 6 | std::uint32_t(value(c));
    if ((have += 6) >= 8) out += char((bits >> (have -= 8)) & 0xff);
  }
  return out;
}

// The values of the `index`-th DataArray named `name` in a .vtu text (its UInt64 byte count checked and dropped);
// empty if there is no such array.
template <class T> std::vector<T> data_array(const std::string& vtu, const std::string& name, int index) {
  std::size_t at = 0;
  for (int i = 0; i <= index; ++i) {
    at = vtu.find("Name=\"" + name + "\"", at + 1);
    if (at == std::string::npos) return {};
  }
  const std::size_t begin = vtu.find('>', at) + 1, end = vtu.find("</DataArray>", begin);
  const std::string bytes = decode_base64(vtu.substr(begin, end - begin));
  std::uint64_t n = 0;
  std::memcpy(&n, bytes.data(), 8);
  EXPECT_EQ(n, bytes.size() - 8) << name;
  std::vector<T> values((bytes.size() - 8) / sizeof(T));
  std::memcpy(values.data(), bytes.data() + 8, values.size() * sizeof(T));
  return values;
}

// The values of a per-cell (or per-point) array that belong to body `b`, as the frame's `body` array of the same
// length says.
template <class T>
std::vector<T> of_body(const std::vector<T>& values, const std::vector<std::int32_t>& body, std::int32_t b) {
  EXPECT_EQ(values.size(), body.size()) << "one body id per value";
  std::vector<T> out;
  for (std::size_t k = 0; k < values.size() && k < body.size(); ++k)
    if (body[k] == b) out.push_back(values[k]);
  return out;
}

// The cells of a .vtu text, each as its connectivity (offsets checked against the connectivity's length).
inline std::vector<std::vector<std::int64_t>> cells_of(const std::string& vtu) {
  const auto connectivity = data_array<std::int64_t>(vtu, "connectivity", 0);
  const auto offsets = data_array<std::int64_t>(vtu, "offsets", 0);
  std::vector<std::vector<std::int64_t>> cells;
  std::int64_t begin = 0;
  for (std::int64_t end : offsets) {
    cells.emplace_back(connectivity.begin() + begin, connectivity.begin() + end);
    begin = end;
  }
  EXPECT_EQ(std::size_t(begin), connectivity.size()) << "the last offset is the connectivity's length";
  return cells;
}

}  // namespace pbd::test
