#include "eval/loop_closure_views.h"

#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "eval/html_escape.h"
#include "memloop/errors.h"
#include "memloop/evaluation.h"
#include "memloop/image_sequence.h"

namespace memloop {
namespace {

constexpr int kThumbnailWidth = 240;

std::string Base64(const std::vector<unsigned char>& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t left = bytes.size() - i;
    const unsigned value =
        bytes[i] << 16 | (left > 1 ? bytes[i + 1] << 8 : 0) | (left > 2 ? bytes[i + 2] : 0);
    text += kAlphabet[value >> 18 & 63];
    text += kAlphabet[value >> 12 & 63];
    text += left > 1 ? kAlphabet[value >> 6 & 63] : '=';
    text += left > 2 ? kAlphabet[value & 63] : '=';
  }
  return text;
}

// A JPEG thumbnail as an <img> with a data: URL (the page stays one file).
std::string Thumbnail(const cv::Mat& image, const std::string& alt) {
  cv::Mat small;
  const double scale = std::min(1.0, double(kThumbnailWidth) / image.cols);
  cv::resize(image, small, cv::Size(), scale, scale, cv::INTER_AREA);
  std::vector<unsigned char> jpeg;
  cv::imencode(".jpg", small, jpeg, {cv::IMWRITE_JPEG_QUALITY, 80});
  return "<img alt=\"" + alt + "\" width=\"" + std::to_string(small.cols) + "\" height=\"" +
         std::to_string(small.rows) + "\" src=\"data:image/jpeg;base64," + Base64(jpeg) + "\">";
}

// The images of `wanted`, found by the names the run's rows give them: a folder's files, or a
// video's frames ("frame N", the video's frame number, also when the run sampled it with --rate).
std::map<ImageIndex, cv::Mat> ReadImages(const std::set<ImageIndex>& wanted,
                                         const std::vector<RunRow>& rows,
                                         const std::string& images) {
  std::map<std::string, ImageIndex> by_name;
  for (const RunRow& row : rows) {
    if (wanted.count(row.image)) by_name[row.name] = row.image;
  }
  std::map<ImageIndex, cv::Mat> read;
  if (std::filesystem::is_directory(images)) {
    for (const auto& [name, index] : by_name) {
      cv::Mat image = cv::imread(images + "/" + name, cv::IMREAD_COLOR);
      if (image.empty()) {
        throw InputError(images, "has no readable image '" + name + "' (image " +
                                     std::to_string(index) +
                                     " of the run): give the folder the run read");
      }
      read[index] = image;
    }
    return read;
  }
  const auto sequence = ImageSequence::Open(images);  // every frame: names are frame numbers
  Frame frame;
  while (read.size() < by_name.size() && sequence->Next(&frame)) {
    const auto found = by_name.find(frame.name);
    if (found != by_name.end() && !frame.image.empty()) read[found->second] = frame.image.clone();
  }
  for (const auto& [name, index] : by_name) {
    if (!read.count(index)) {
      throw InputError(images, "has no " + name + " (image " + std::to_string(index) +
                                   " of the run): give the video the run read");
    }
  }
  return read;
}

// "image 12 (frame 25)": the run's index and the image's name.
std::string Alt(ImageIndex index, const std::map<ImageIndex, std::string>& names) {
  const auto name = names.find(index);
  return "image " + std::to_string(index) +
         (name == names.end() ? "" : " (" + HtmlEscaped(name->second) + ")");
}

const char* VerdictClass(const std::string& verdict) {
  return verdict == "false" ? "false" : verdict == "ignored" ? "ignored" : "true";
}

}  // namespace

std::vector<LoopClosureView> AcceptedLoopClosures(const std::vector<RunRow>& rows,
                                                  const GroundTruth* truth) {
  std::vector<LoopClosureView> views;
  for (const RunRow& row : rows) {
    if (row.matched_images.empty()) continue;
    LoopClosureView view{row.image, row.matched_images.front(), row.hypothesis_value, ""};
    if (truth != nullptr) {
      const Verdict verdict = Judge(row.image, row.matched_images, *truth);
      view.verdict = verdict == Verdict::kTrue      ? "true"
                     : verdict == Verdict::kIgnored ? "ignored"
                                                    : "false";
      // The image that makes the verdict, if one does.
      const GroundTruth::Label wanted =
          verdict == Verdict::kTrue ? GroundTruth::kLoop : GroundTruth::kIgnored;
      for (ImageIndex match : row.matched_images) {
        if (verdict != Verdict::kFalse && match < row.image &&
            truth->At(row.image, match) == wanted) {
          view.match = match;
          break;
        }
      }
    }
    views.push_back(view);
  }
  return views;
}

std::vector<LoopClosureView> ChooseViews(const std::vector<LoopClosureView>& views, int max_views) {
  std::vector<LoopClosureView> chosen;
  for (const char* verdict : {"false", "ignored", "true", ""}) {
    std::vector<LoopClosureView> group;
    for (const LoopClosureView& view : views) {
      if (view.verdict == verdict) group.push_back(view);
    }
    const size_t room = static_cast<size_t>(std::max(0, max_views)) - chosen.size();
    if (group.size() <= room) {
      chosen.insert(chosen.end(), group.begin(), group.end());
      continue;
    }
    for (size_t k = 0; k < room; ++k) chosen.push_back(group[k * group.size() / room]);
  }
  return chosen;
}

std::string LoopClosureViewsSection(const std::vector<LoopClosureView>& views,
                                    const std::vector<RunRow>& rows, const std::string& images,
                                    int max_views) {
  const std::vector<LoopClosureView> chosen = ChooseViews(views, max_views);
  std::set<ImageIndex> wanted;
  for (const LoopClosureView& view : chosen) wanted.insert({view.query, view.match});
  const std::map<ImageIndex, cv::Mat> read = ReadImages(wanted, rows, images);
  std::string html = "<section id=\"loop-closures\">\n<h2>Loop closures, image by image</h2>\n";
  html += "<p class=\"caption\">The query image (left) and the matched image (right) of " +
          (chosen.size() == views.size()
               ? "every loop closure"
               : std::to_string(chosen.size()) + " of the " + std::to_string(views.size()) +
                     " loop closures (false positives first, the others spread evenly)") +
          ".</p>\n<table class=\"views\">\n";
  std::map<ImageIndex, std::string> names;
  for (const RunRow& row : rows) names[row.image] = row.name;
  char line[256];
  for (const LoopClosureView& view : chosen) {
    std::snprintf(line, sizeof(line), "image %d &rarr; image %d, p=%.3f%s%s", view.query,
                  view.match, view.probability, view.verdict.empty() ? "" : ": ",
                  view.verdict.c_str());
    html += std::string("<tr class=\"") + VerdictClass(view.verdict) + "\"><td>" + line +
            "</td><td>" + Thumbnail(read.at(view.query), Alt(view.query, names)) + "</td><td>" +
            Thumbnail(read.at(view.match), Alt(view.match, names)) + "</td></tr>\n";
  }
  return html + "</table>\n</section>\n";
}

}  // namespace memloop
