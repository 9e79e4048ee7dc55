// Parameter files (`--config FILE`): INI lines read through the same registry as --set.
#include <fstream>
#include <string>

#include "memloop/errors.h"
#include "memloop/params.h"
#include "util/excerpt.h"

namespace memloop {
namespace {

std::string Trimmed(const std::string& text) {
  const size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

// A comment runs from '#' or ';' at the start of the line or after a blank to its end.
std::string WithoutComment(const std::string& line) {
  for (size_t i = 0; i < line.size(); ++i) {
    if ((line[i] == '#' || line[i] == ';') && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t'))
      return line.substr(0, i);
  }
  return line;
}

}  // namespace

void ApplyParameterFile(Options& options, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read the parameter file");
  std::string section;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string text = Trimmed(WithoutComment(line));
    const std::string where = "line " + std::to_string(number) + ": ";
    if (line.find('\0') != std::string::npos) {
      throw InputError(path, where + "holds a NUL byte: a parameter file is text");
    }
    if (text.empty()) continue;
    if (text.front() == '[') {
      if (text.back() != ']') throw InputError(path, where + "a section must end with ']'");
      section = Trimmed(text.substr(1, text.size() - 2));
      continue;
    }
    const size_t equals = text.find('=');
    if (equals == std::string::npos) {
      throw InputError(path, where + "expected 'name = value', got '" + Excerpt(text) + "'");
    }
    const std::string name = Trimmed(text.substr(0, equals));
    const std::string key = section.empty() ? name : section + "." + name;
    try {
      SetParameter(options, key + "=" + Trimmed(text.substr(equals + 1)));
    } catch (const ParameterError& error) {
      throw InputError(path, where + error.what());
    }
  }
  if (in.bad()) throw InputError(path, "reading the parameter file failed");
}

}  // namespace memloop
