// The one exception hierarchy of memloop. Every error that user input (images, files, parameters,
// databases, ground truth) can trigger is one of these; the message names the input, the problem
// and, when known, the fix. Programming errors are asserts, never these.
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>

namespace memloop {

// A map's name as messages show it: a server's URI (postgresql://...) without its password, in
// the user part or as a parameter; any other name as it is.
inline std::string WithoutPassword(std::string name) {
  if (name.rfind("postgresql://", 0) != 0 && name.rfind("postgres://", 0) != 0) return name;
  const size_t authority = name.find("://") + 3;
  const size_t at = name.find('@', authority);
  const size_t colon = name.find(':', authority);
  if (at != std::string::npos && name.find_first_of("/?", authority) > at && colon < at) {
    name.erase(colon, at - colon);
  }
  const size_t query = name.find('?');
  for (size_t at = query;
       query != std::string::npos && (at = name.find("password=", at)) != std::string::npos; ++at) {
    if (name[at - 1] != '?' && name[at - 1] != '&') continue;  // another parameter's tail
    const size_t value = at + 9;
    const size_t end = std::min(name.find('&', value), name.size());
    name.replace(value, end - value, "...");
  }
  return name;
}

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A parameter name that does not exist or a value outside its range.
class ParameterError : public Error {
 public:
  ParameterError(std::string key, const std::string& message)
      : Error(message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// A file or folder that cannot be used: missing, unreadable, corrupt, foreign.
class InputError : public Error {
 public:
  // A server's URI is named without its password (WithoutPassword).
  InputError(const std::string& path, const std::string& problem)
      : Error(WithoutPassword(path) + ": " + problem), path_(WithoutPassword(path)) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The Long-Term Memory database cannot be opened, is not memloop's, or is damaged.
class DatabaseError : public InputError {
 public:
  using InputError::InputError;
};

}  // namespace memloop
