// Plots drawn by gnuplot (Debian's gnuplot-nox), returned as SVG text.
#pragma once

#include <string>

namespace memloop {

// Runs `script` (gnuplot commands; data inline as datablocks) with an SVG terminal of the given
// size and returns the SVG. Throws Error when gnuplot is missing or fails, with its message.
std::string RenderSvg(const std::string& script, int width, int height);

}  // namespace memloop
