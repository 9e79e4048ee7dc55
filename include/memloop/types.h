// Identifiers shared by the whole library.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace memloop {

// A location (a node of the map graph). Ids start at 1 and grow with time, so a smaller id is an
// older location: Transfer (paper III-F) uses that order to break weight ties.
using LocationId = int;
// The virtual place S_t = -1 of the Bayes filter: "L_t is a new location" (paper III-C).
inline constexpr LocationId kVirtualPlace = -1;
// No location (e.g. "no loop closure").
inline constexpr LocationId kNoLocation = 0;

// A visual word of the incremental dictionary. Ids start at 1 and are never reused.
using WordId = int;
inline constexpr WordId kNoWord = 0;

// Index of an image in the processed sequence (0-based, in processing order).
using ImageIndex = int;
inline constexpr ImageIndex kNoImage = -1;

// A time stamp in seconds (a dataset's clock, a video's time from its start, a camera's
// computer clock since 1970); NaN: unknown.
inline constexpr double kNoTimestamp = std::numeric_limits<double>::quiet_NaN();
inline bool HasTimestamp(double timestamp) { return !std::isnan(timestamp); }

}  // namespace memloop
