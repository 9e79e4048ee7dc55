// How the generated sequences are written (`memloop generate --layout`), with their ground truth
// (ground_truth_pairs.csv, by the names a run gives the frames).
#pragma once

#include <string>

namespace memloop {

enum class GeneratedLayout {
  kImages,   // images/1.png .. N.png: the layout of ../shared/datasets
  kTum,      // a TUM RGB-D folder: rgb/1.png .. N.png and rgb.txt, 10 Hz from t = 1000 s
  kRos2Bag,  // a ROS 2 bag folder ros2_bag/ (sqlite3): /camera/image_raw, the same times
};
// "images", "tum", "ros2-bag"; ParameterError naming `--layout` otherwise.
GeneratedLayout ParseGeneratedLayout(const std::string& name);

}  // namespace memloop
