#include "eval/gnuplot.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "memloop/errors.h"

namespace memloop {

std::string RenderSvg(const std::string& script, int width, int height) {
  namespace fs = std::filesystem;
  static int counter = 0;
  const fs::path base = fs::temp_directory_path() / ("memloop-plot-" + std::to_string(getpid()) +
                                                     "-" + std::to_string(counter++));
  const std::string script_path = base.string() + ".gp";
  const std::string errors_path = base.string() + ".err";
  {
    std::ofstream out(script_path);
    out << "set terminal svg size " << width << "," << height
        << " dynamic enhanced font 'sans,11' background rgb 'white'\n"
        << script << "\n";
  }
  const std::string command = "gnuplot '" + script_path + "' 2>'" + errors_path + "'";
  FILE* pipe = popen(command.c_str(), "r");
  std::string svg;
  if (pipe != nullptr) {
    char buffer[8192];
    size_t read = 0;
    while ((read = fread(buffer, 1, sizeof(buffer), pipe)) > 0) svg.append(buffer, read);
  }
  const int status = pipe ? pclose(pipe) : -1;
  std::ifstream errors_file(errors_path);
  const std::string errors(std::istreambuf_iterator<char>(errors_file), {});
  std::error_code ignored;
  fs::remove(script_path, ignored);
  fs::remove(errors_path, ignored);
  const int exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  if (exit_code == 127) {  // the shell found no gnuplot
    throw Error("memloop report needs gnuplot: install the Debian package gnuplot-nox");
  }
  if (exit_code != 0 || svg.find("<svg") == std::string::npos) {
    throw Error("gnuplot failed to draw a figure: " + errors);
  }
  return svg.substr(svg.find("<svg"));  // without the XML prologue, to inline it in HTML
}

}  // namespace memloop
