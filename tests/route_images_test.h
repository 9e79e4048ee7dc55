// A test suite sharing the short generated route, written once as images (CLI tests).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "memloop/synthetic_route.h"
#include "short_route.h"
#include "temp_dir.h"

namespace memloop::testing {

// `Suite` names the deriving suite, so that each suite has its own folder.
template <typename Suite>
class RouteImagesTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new TempDir();
    SyntheticRoute(ShortRoute()).Write(folder_->path().string());
  }
  static void TearDownTestSuite() {
    delete folder_;
    folder_ = nullptr;
  }
  static std::string Images() { return folder_->File("images"); }

  static inline TempDir* folder_ = nullptr;
  TempDir dir_;  // this test's own files
};

}  // namespace memloop::testing
