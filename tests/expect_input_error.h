// The InputError a call must throw: naming `path`, its message holding `reason`.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "memloop/errors.h"

namespace memloop::testing {

template <typename Open>
void ExpectInputError(Open open, const std::string& path, const std::string& reason) {
  try {
    open();
    FAIL() << "no error for " << path;
  } catch (const InputError& error) {
    EXPECT_EQ(error.path(), path);
    EXPECT_NE(std::string(error.what()).find(reason), std::string::npos) << error.what();
  }
}

}  // namespace memloop::testing
