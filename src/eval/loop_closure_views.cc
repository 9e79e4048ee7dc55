#include "eval/loop_closure_views.h"

#include <algorithm>
#include <cstdio>
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
  if (wanted.empty()) return read;
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

// The most recent earlier image of the same place (the revisit's nearest in time), or kNoImage.
ImageIndex LatestTrueMatch(ImageIndex query, const GroundTruth& truth) {
  for (ImageIndex match = std::min(query, truth.size()) - 1; match >= 0; --match) {
    if (truth.IsLoop(query, match)) return match;
  }
  return kNoImage;
}

const char* VerdictClass(const std::string& verdict) {
  return verdict == "false"     ? "false"
         : verdict == "ignored" ? "ignored"
         : verdict == "missed"  ? "missed"
                                : "true";
}

// "0101.jpg" (the image's name in the run), or "image 12" for a row without one.
std::string NameOf(ImageIndex index, const std::map<ImageIndex, std::string>& names) {
  const auto name = names.find(index);
  return name == names.end() || name->second.empty() ? "image " + std::to_string(index)
                                                     : HtmlEscaped(name->second);
}

// The row's words: what was matched, its value and verdict, and the true match when it is not.
std::string Description(const LoopClosureView& view,
                        const std::map<ImageIndex, std::string>& names) {
  char value[64];
  std::snprintf(value, sizeof(value), "p=%.3f", view.probability);
  const std::string chosen =
      view.match == kNoImage ? "no earlier place" : NameOf(view.match, names);
  std::string text = "<b>" + NameOf(view.query, names) + "</b> ";
  if (view.verdict == "missed") {
    text += "<span class=\"verdict\">missed</span>: highest hypothesis " + chosen + ", " + value;
  } else {
    text += "&rarr; " + chosen + ", " + value;
    if (!view.verdict.empty()) text += ": <span class=\"verdict\">" + view.verdict + "</span>";
  }
  if (view.true_match != kNoImage) text += "; true match " + NameOf(view.true_match, names);
  return text;
}

}  // namespace

std::vector<LoopClosureView> AcceptedLoopClosures(const std::vector<RunRow>& rows,
                                                  const GroundTruth* truth) {
  std::vector<LoopClosureView> views;
  for (const RunRow& row : rows) {
    if (row.matched_images.empty() || !row.matched_robot.empty()) continue;  // own places
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
      if (verdict == Verdict::kFalse) view.true_match = LatestTrueMatch(row.image, *truth);
    }
    views.push_back(view);
  }
  return views;
}

std::vector<LoopClosureView> MissedLoopClosures(const std::vector<RunRow>& rows,
                                                const GroundTruth& truth) {
  std::vector<LoopClosureView> views;
  for (const RunRow& row : rows) {
    if (!row.matched_images.empty() || row.image >= truth.size()) continue;
    const ImageIndex true_match = LatestTrueMatch(row.image, truth);
    if (true_match == kNoImage) continue;
    const ImageIndex chosen =
        row.hypothesis_images.empty() ? kNoImage : row.hypothesis_images.front();
    views.push_back({row.image, chosen, row.hypothesis_value, "missed", true_match});
  }
  return views;
}

std::vector<LoopClosureView> ChooseViews(const std::vector<LoopClosureView>& views, int max_views) {
  std::vector<LoopClosureView> chosen;
  for (const char* verdict : {"false", "missed", "ignored", "true", ""}) {
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
  const std::vector<LoopClosureView> listed = ChooseViews(views, kMaxListedViews);
  std::set<ImageIndex> shown;  // the queries whose rows show images
  std::set<ImageIndex> wanted;
  if (!images.empty()) {
    for (const LoopClosureView& view : ChooseViews(views, max_views)) {
      shown.insert(view.query);
      for (ImageIndex image : {view.query, view.match, view.true_match}) {
        if (image != kNoImage) wanted.insert(image);
      }
    }
  }
  const std::map<ImageIndex, cv::Mat> read = ReadImages(wanted, rows, images);
  std::map<ImageIndex, std::string> names;
  for (const RunRow& row : rows) names[row.image] = row.name;
  int misses = 0;
  for (const LoopClosureView& view : views) misses += view.verdict == "missed";
  const size_t accepted = views.size() - misses;
  std::string html = "<section id=\"loop-closures\">\n<h2>Loop closures and misses</h2>\n";
  html += "<p class=\"caption\">" + std::to_string(accepted) + " loop closures accepted" +
          (misses > 0 ? ", " + std::to_string(misses) + (misses == 1 ? " image" : " images") +
                            " with a true match missed"
                      : "") +
          (listed.size() < views.size() ? "; " + std::to_string(listed.size()) +
                                              " listed (false positives and misses "
                                              "first, the others spread evenly)"
                                        : "") +
          (images.empty() ? ""
                          : "; " + std::to_string(shown.size()) +
                                " with their images: the query, the place chosen and the "
                                "true match") +
          ".</p>\n<table class=\"views\">\n" +
          (shown.empty() ? ""
                         : "<tr><th></th><th>query</th><th>the place chosen</th><th>its true "
                           "match (when not the place chosen)</th></tr>\n");
  const auto thumbnail = [&](ImageIndex image) {
    return image == kNoImage ? std::string() : Thumbnail(read.at(image), Alt(image, names));
  };
  for (const LoopClosureView& view : listed) {
    html += std::string("<tr id=\"pair-") + std::to_string(view.query) + "\" class=\"" +
            VerdictClass(view.verdict) + "\"><td>" + Description(view, names) + "</td>";
    if (shown.count(view.query)) {
      html += "<td>" + thumbnail(view.query) + "</td><td>" + thumbnail(view.match) + "</td><td>" +
              thumbnail(view.true_match) + "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</table>\n</section>\n";
}

}  // namespace memloop
