// The one exception hierarchy of memloop. Every error that user input (images, files, parameters,
// databases, ground truth) can trigger is one of these; the message names the input, the problem
// and, when known, the fix. Programming errors are asserts, never these.
#pragma once

#include <stdexcept>
#include <string>

namespace memloop {

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
  InputError(std::string path, const std::string& problem)
      : Error(path + ": " + problem), path_(std::move(path)) {}
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
