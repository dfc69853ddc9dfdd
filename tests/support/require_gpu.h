// Skips a GPU test, with the reason, where no CUDA device answers.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "cuda/engine/engine.h"

#define REQUIRE_GPU()                                                                      \
  do {                                                                                     \
    std::string why_no_gpu;                                                                \
    if (!pd::cuda_device_available(&why_no_gpu)) GTEST_SKIP() << "no GPU: " << why_no_gpu; \
  } while (0)
