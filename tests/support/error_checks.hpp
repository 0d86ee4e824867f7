#pragma once
// Shared checks for bad-input tests: the message of the pbd::Error an input raises, and text edits of a good input.
#include "pbd/error.hpp"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace pbd::test {

/// The message of the pbd::Error that `load` throws (a failure if it throws nothing or something else).
template <class Load> std::string error_of(Load&& load) {
  try {
    load();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a pbd::Error: " << e.what();
    return {};
  }
  ADD_FAILURE() << "accepted";
  return {};
}

/// Expects `message` to contain every one of `words` and to stay short (no megabyte echo of the input).
inline void expect_words(const std::string& message, std::initializer_list<std::string> words) {
  for (const auto& w : words) EXPECT_NE(message.find(w), std::string::npos) << "no \"" << w << "\" in: " << message;
  EXPECT_LT(message.size(), 400u) << message.substr(0, 400);
}

/// `text` with the first `from` replaced by `to` (a failure, and `text` unchanged, if `from` is not in it).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace pbd::test
