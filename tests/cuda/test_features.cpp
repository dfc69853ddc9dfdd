// Feature sets: runtime flags reach the matching compile-time instantiation.
#include "cuda/features.h"

#include <gtest/gtest.h>

namespace pd {
namespace {

TEST(Features, StaticBoolsTurnsEveryFlagIntoItsType) {
  for (int mask = 0; mask < 8; ++mask) {
    int seen = -1;
    static_bools(
        [&](auto a, auto b, auto c) {
          seen = int(decltype(a)::value) | int(decltype(b)::value) << 1 | int(decltype(c)::value) << 2;
        },
        bool(mask & 1), bool(mask & 2), bool(mask & 4));
    EXPECT_EQ(seen, mask);
  }
}

TEST(Features, BondBasedMaterialsNeedNoStateBasedPhysics) {
  MaterialTable t;
  t.count = 2;
  t.m[0].model = kBondBased;
  t.m[0].plastic = 1;  // ignored: plasticity is a state-based feature
  t.m[1].model = kBondBased;
  const KernelFeatures f = features_of(t, false);
  EXPECT_FALSE(f.state_based || f.plastic || f.anisotropic || f.contact);
  t.m[1].model = kStateBased;
  t.m[1].plastic = 1;
  const KernelFeatures g = features_of(t, false);
  EXPECT_TRUE(g.state_based && g.plastic);
  EXPECT_FALSE(g.anisotropic);
}

}  // namespace
}  // namespace pd
