#include "input/ros_image.h"

#include <algorithm>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace memloop {
namespace {

// The pixels as a `type` matrix (a copy, in this machine's byte order), or empty with `error`
// when the data is shorter than the size says.
cv::Mat PixelsOf(const RawImage& image, int type, std::string* error) {
  const size_t row_bytes = static_cast<size_t>(image.width) * CV_ELEM_SIZE(type);
  if (image.height == 0 || image.width == 0 || image.step < row_bytes ||
      image.size < static_cast<size_t>(image.height) * image.step) {
    *error = "image data is shorter than its size says (" + std::to_string(image.width) + "x" +
             std::to_string(image.height) + ", step " + std::to_string(image.step) + ", " +
             std::to_string(image.size) + " bytes)";
    return cv::Mat();
  }
  cv::Mat pixels = cv::Mat(static_cast<int>(image.height), static_cast<int>(image.width), type,
                           const_cast<uint8_t*>(image.data), image.step)
                       .clone();
  if (image.big_endian && CV_ELEM_SIZE1(type) > 1) {
    for (int y = 0; y < pixels.rows; ++y) {
      uint8_t* row = pixels.ptr<uint8_t>(y);
      const size_t element = CV_ELEM_SIZE1(type);
      for (size_t x = 0; x < row_bytes; x += element) std::reverse(row + x, row + x + element);
    }
  }
  return pixels;
}

}  // namespace

cv::Mat DecodeRawImage(const RawImage& image, std::string* error) {
  const std::string& encoding = image.encoding;
  int type = -1;
  int conversion = -1;  // to gray or BGR
  if (encoding == "mono8" || encoding == "8UC1") {
    type = CV_8UC1;
  } else if (encoding == "bgr8" || encoding == "8UC3") {
    type = CV_8UC3;
  } else if (encoding == "rgb8") {
    type = CV_8UC3, conversion = cv::COLOR_RGB2BGR;
  } else if (encoding == "bgra8" || encoding == "8UC4") {
    type = CV_8UC4, conversion = cv::COLOR_BGRA2BGR;
  } else if (encoding == "rgba8") {
    type = CV_8UC4, conversion = cv::COLOR_RGBA2BGR;
  } else if (encoding == "mono16" || encoding == "16UC1") {
    type = CV_16UC1;
  } else {
    *error = "image encoding '" + encoding +
             "' is not read (mono8, mono16, bgr8, rgb8, bgra8, rgba8 are; or CompressedImage)";
    return cv::Mat();
  }
  const cv::Mat pixels = PixelsOf(image, type, error);
  if (pixels.empty()) return pixels;
  cv::Mat result;
  if (type == CV_16UC1) {
    // The range the image uses, to 8 bits: a 16-bit camera's values seldom fill 65,535.
    double low = 0, high = 0;
    cv::minMaxLoc(pixels, &low, &high);
    pixels.convertTo(result, CV_8U, high > low ? 255.0 / (high - low) : 1,
                     high > low ? -low * 255.0 / (high - low) : 0);
    return result;
  }
  if (conversion >= 0) {
    cv::cvtColor(pixels, result, conversion);
    return result;
  }
  return pixels;
}

cv::Mat DecodeRawDepth(const RawImage& image, double units_per_metre, std::string* error) {
  const std::string& encoding = image.encoding;
  const bool millimetre_like = encoding == "16UC1" || encoding == "mono16";
  if (!millimetre_like && encoding != "32FC1") {
    *error = "depth encoding '" + encoding + "' is not read (16UC1, mono16 or 32FC1 are)";
    return cv::Mat();
  }
  const cv::Mat pixels = PixelsOf(image, millimetre_like ? CV_16UC1 : CV_32FC1, error);
  if (pixels.empty()) return pixels;
  cv::Mat metres;
  pixels.convertTo(metres, CV_32F, millimetre_like ? 1.0 / units_per_metre : 1.0);
  cv::patchNaNs(metres, 0);  // no reading
  metres.setTo(0, (metres < 0) | (metres > std::numeric_limits<float>::max()));
  return metres;
}

cv::Mat DecodeCompressedImage(const uint8_t* data, size_t size, std::string* error) {
  cv::Mat image;
  try {
    if (size > 0)
      image = cv::imdecode(cv::Mat(1, static_cast<int>(size), CV_8U, const_cast<uint8_t*>(data)),
                           cv::IMREAD_COLOR);
  } catch (const cv::Exception& exception) {
    *error = exception.what();
  }
  if (image.empty() && error->empty()) *error = "compressed image data that does not decode";
  return image;
}

}  // namespace memloop
