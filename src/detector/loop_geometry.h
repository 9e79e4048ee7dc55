// The geometry between two views of a loop closure, from the words they share: the fundamental
// matrix's inliers and, given the intrinsics, the relative pose (essential matrix).
#pragma once

#include "memloop/loop_geometry.h"
#include "memloop/options.h"
#include "vocabulary/signature.h"

namespace memloop {

// RANSAC is seeded: the same views give the same geometry.
LoopGeometry EstimateLoopGeometry(const Signature& query, const Signature& match,
                                  const CameraIntrinsics& intrinsics,
                                  const VerificationOptions& options);

}  // namespace memloop
