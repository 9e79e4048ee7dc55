// FLANN, made repeatable. Debian's FLANN 1.9.2 (as upstream 1.9.2) shuffles the points before
// building each kd-tree with std::shuffle seeded from std::random_device, so two forests built from
// the same points differ, flann::seed_random cannot help, and two runs of the same images give
// different words. While FLANN's headers are read, random_device is renamed to minstd_rand0, a
// standard engine whose default seed is fixed: every build shuffles the same way, and the rest of
// FLANN's randomness (std::rand) is seeded by flann::seed_random. Include FLANN only through here.
#pragma once

#include <random>

#define random_device minstd_rand0
#include <flann/flann.hpp>
#undef random_device
