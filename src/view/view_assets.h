// The viewer's page, script and style sheet (src/view/assets/), built into the program by CMake
// (cmake/embed_assets.cmake) so that `memloop view` needs no file beside it and works offline.
#pragma once

#include <string_view>
#include <vector>

namespace memloop {

struct ViewerAsset {
  const char* path;  // "/", "/viewer.js", "/viewer.css"
  const char* type;  // MIME type
  std::string_view content;
};

const std::vector<ViewerAsset>& ViewerAssets();

}  // namespace memloop
