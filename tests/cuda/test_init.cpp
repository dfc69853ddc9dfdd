// Kernel 1 body: Levine eq. 5, tau' = tau - alpha min(0, eps_min).
#include <gtest/gtest.h>

#include "cuda/kernels/init.h"

namespace pd {
namespace {

TEST(Init, CompressionStrengthensTheLimit) {
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0.25), real(-4e-3)), real(2e-3));
}

TEST(Init, TensionLeavesTheLimit) {
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0.25), real(5e-4)), real(1e-3));
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0.25), real(0)), real(1e-3));
}

TEST(Init, AlphaZeroDisablesStrengthening) {
  EXPECT_FLOAT_EQ(effective_strain_limit(real(1e-3), real(0), real(-1)), real(1e-3));
}

}  // namespace
}  // namespace pd
