// Videos and cameras, through OpenCV's VideoCapture.
#pragma once

#include <memory>
#include <string>

#include "memloop/image_sequence.h"

namespace memloop {

// `rate_hz` > 0: the frames whose timestamps first reach each multiple of 1 / rate_hz.
std::unique_ptr<ImageSequence> OpenVideo(const std::string& path, double rate_hz);

// Throws ParameterError for a rate that is not a finite number >= 0 (NaN included).
void CheckSequenceOptions(const SequenceOptions& options);

}  // namespace memloop
