#include "memloop/feature_extractor.h"

#include "features/orb_extractor.h"
#include "features/sift_extractor.h"
#include "features/surf_extractor.h"
#include "features/upsampled_extractor.h"
#include "memloop/errors.h"

namespace memloop {

namespace {

std::unique_ptr<FeatureExtractor> CreateBackend(const FeatureOptions& options) {
  if (options.type == "surf") return std::make_unique<SurfExtractor>(options);
  if (options.type == "sift") return std::make_unique<SiftExtractor>(options);
  if (options.type == "orb") return std::make_unique<OrbExtractor>(options);
  throw ParameterError("features.type",
                       "Invalid parameter features.type = '" + options.type +
                           "': unknown feature backend (available: surf, sift, orb)");
}

}  // namespace

std::unique_ptr<FeatureExtractor> FeatureExtractor::Create(const FeatureOptions& options) {
  std::unique_ptr<FeatureExtractor> backend = CreateBackend(options);
  if (options.min_image_side <= 0) return backend;
  return std::make_unique<UpsampledExtractor>(std::move(backend), options.min_image_side);
}

}  // namespace memloop
