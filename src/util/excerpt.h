// What an error message quotes of a value the user gave: all of it when short, its start and its
// length when long (a 10 MB line of a parameter file is named, not echoed).
#pragma once

#include <string>

namespace memloop {

inline std::string Excerpt(const std::string& text) {
  constexpr size_t kWhole = 60;  // quoted in full up to this many characters
  constexpr size_t kStart = 40;  // else this many, then the length
  if (text.size() <= kWhole) return text;
  return text.substr(0, kStart) + "... (" + std::to_string(text.size()) + " characters)";
}

}  // namespace memloop
