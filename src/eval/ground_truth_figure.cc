#include "eval/ground_truth_figure.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "eval/html_escape.h"

namespace memloop {
namespace {

constexpr double kSide = 560;  // the plot's square, px
constexpr double kLeft = 64;
constexpr double kTop = 16;
constexpr double kLegendWidth = 190;

struct Style {
  const char* verdict;
  const char* label;
  const char* fill;
  const char* stroke;
  double radius;
};
// Drawn in this order: the rarest and worst last, on top.
constexpr Style kStyles[] = {{"true", "true positive", "#2ca02c", "#2ca02c", 2.6},
                             {"ignored", "on an ignored pair", "none", "#9467bd", 3.2},
                             {"missed", "missed (at its true match)", "none", "#ff7f0e", 3.2},
                             {"false", "false positive", "#d62728", "#7f0000", 4.2}};

// Ticks at 1, 2 or 5 x 10^k, five to ten of them.
double TickStep(int count) {
  const double raw = std::max(1.0, count / 6.0);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0, 10.0}) {
    if (factor * power >= raw) return factor * power;
  }
  return 10 * power;
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", value);
  return text;
}

}  // namespace

std::string GroundTruthSvg(const GroundTruth& truth, const std::vector<LoopClosureView>& views,
                           const std::set<ImageIndex>& listed,
                           const std::vector<std::string>& names) {
  const int count = std::max(1, truth.size());
  const double scale = kSide / count;
  const auto x = [&](ImageIndex match) { return Number(kLeft + (match + 0.5) * scale); };
  const auto y = [&](ImageIndex query) { return Number(kTop + (query + 0.5) * scale); };
  const auto name = [&](ImageIndex image) {
    return image >= 0 && image < static_cast<ImageIndex>(names.size()) && !names[image].empty()
               ? HtmlEscaped(names[image])
               : "image " + std::to_string(image);
  };
  const double width = kLeft + kSide + 24 + kLegendWidth;
  const double height = kTop + kSide + 48;
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Number(width) +
                    "\" height=\"" + Number(height) + "\" viewBox=\"0 0 " + Number(width) + " " +
                    Number(height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg += "<rect x=\"" + Number(kLeft) + "\" y=\"" + Number(kTop) + "\" width=\"" + Number(kSide) +
         "\" height=\"" + Number(kSide) + "\" fill=\"#fff\" stroke=\"#444\"/>\n";
  // Axes: image indices, the query's down as in the matrix.
  const double step = TickStep(count);
  for (double tick = 0; tick < count; tick += step) {
    const double at = tick * scale;
    svg += "<text x=\"" + Number(kLeft + at) + "\" y=\"" + Number(kTop + kSide + 16) +
           "\" text-anchor=\"middle\">" + std::to_string(static_cast<int>(tick)) + "</text>";
    svg += "<text x=\"" + Number(kLeft - 6) + "\" y=\"" + Number(kTop + at + 4) +
           "\" text-anchor=\"end\">" + std::to_string(static_cast<int>(tick)) + "</text>\n";
  }
  svg += "<text x=\"" + Number(kLeft + kSide / 2) + "\" y=\"" + Number(kTop + kSide + 36) +
         "\" text-anchor=\"middle\">Matched image</text>\n<text transform=\"translate(14 " +
         Number(kTop + kSide / 2) + ") rotate(-90)\" text-anchor=\"middle\">Query image</text>\n";
  // Ground-truth pairs: one grey cell each, at least a pixel and a half.
  const std::string cell = Number(std::max(1.5, scale));
  svg += "<g fill=\"#c7c7c7\">";
  for (ImageIndex query = 0; query < truth.size(); ++query) {
    for (ImageIndex match = 0; match < query; ++match) {
      if (!truth.IsLoop(query, match)) continue;
      svg += "<rect x=\"" + Number(kLeft + match * scale) + "\" y=\"" +
             Number(kTop + query * scale) + "\" width=\"" + cell + "\" height=\"" + cell + "\"/>";
    }
  }
  svg += "</g>\n";
  for (const Style& style : kStyles) {
    for (const LoopClosureView& view : views) {
      if (view.verdict != style.verdict) continue;
      const ImageIndex column = view.verdict == "missed" ? view.true_match : view.match;
      if (column == kNoImage) continue;
      const std::string point = "<circle cx=\"" + x(column) + "\" cy=\"" + y(view.query) +
                                "\" r=\"" + Number(style.radius) + "\" fill=\"" + style.fill +
                                "\" stroke=\"" + style.stroke + "\" stroke-width=\"1.2\"><title>" +
                                name(view.query) + " &rarr; " + name(column) + ": " + style.label +
                                "</title></circle>";
      svg += listed.count(view.query)
                 ? "<a href=\"#pair-" + std::to_string(view.query) + "\">" + point + "</a>\n"
                 : point + "\n";
    }
  }
  // The legend, right of the plot.
  double row = kTop + 14;
  const double legend = kLeft + kSide + 24;
  svg += "<rect x=\"" + Number(legend) + "\" y=\"" + Number(row - 5) +
         "\" width=\"8\" height=\"8\" fill=\"#c7c7c7\"/><text x=\"" + Number(legend + 16) +
         "\" y=\"" + Number(row + 3) + "\">ground truth</text>\n";
  for (const Style& style : kStyles) {
    row += 20;
    svg += "<circle cx=\"" + Number(legend + 4) + "\" cy=\"" + Number(row - 1) + "\" r=\"" +
           Number(style.radius) + "\" fill=\"" + style.fill + "\" stroke=\"" + style.stroke +
           "\" stroke-width=\"1.2\"/><text x=\"" + Number(legend + 16) + "\" y=\"" +
           Number(row + 3) + "\">" + style.label + "</text>\n";
  }
  return svg + "</svg>";
}

}  // namespace memloop
