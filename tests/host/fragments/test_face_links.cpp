// FaceLinks: what holds two touching elements together, with and without a bond between them.
#include "host/fragments/face_links.h"

#include <gtest/gtest.h>

#include "tests/host/fragments/fragment_fixtures.h"

namespace pd {
namespace {

using testing::bond_lists;
using testing::break_bond;

// A bonded pair holds while its bond is intact from both ends.
TEST(FaceLinks, BondedPairHoldsUntilItsBondBreaksFromEitherEnd) {
  for (int end = 0; end < 2; ++end) {
    BondLists bonds = bond_lists({{1}, {0}});
    const FaceLinks links({{0, 1}}, bonds);
    EXPECT_EQ(links.indirect(), 0u);
    EXPECT_EQ(links.unlinked(), 0u);
    EXPECT_TRUE(links.intact(0, bonds.neighbor.data()));
    ASSERT_TRUE(end == 0 ? break_bond(bonds, 0, 1) : break_bond(bonds, 1, 0));
    EXPECT_FALSE(links.intact(0, bonds.neighbor.data()));
  }
}

// 0 and 3 touch without a bond; 1 and 2 are bonded to both. The pair holds while either common
// neighbour keeps both its bonds, and parts once neither does.
TEST(FaceLinks, UnbondedPairHoldsThroughCommonNeighbours) {
  BondLists bonds = bond_lists({{1, 2}, {0, 3}, {0, 3}, {1, 2}});
  const FaceLinks links({{0, 3}}, bonds);
  EXPECT_EQ(links.indirect(), 1u);
  EXPECT_TRUE(links.linked(0));
  EXPECT_TRUE(links.intact(0, bonds.neighbor.data()));
  break_bond(bonds, 0, 1);  // the path through 1 is gone, the one through 2 holds
  EXPECT_TRUE(links.intact(0, bonds.neighbor.data()));
  break_bond(bonds, 2, 3);  // the path through 2, broken in the neighbour's family only
  EXPECT_FALSE(links.intact(0, bonds.neighbor.data()));
}

// No bond and no common neighbour: a crack from the start, counted.
TEST(FaceLinks, PairWithNoBondPathIsACrackFromTheStart) {
  const BondLists bonds = bond_lists({{1}, {0}, {3}, {2}});
  const FaceLinks links({{0, 1}, {1, 2}}, bonds);
  EXPECT_EQ(links.size(), 2u);
  EXPECT_EQ(links.unlinked(), 1u);
  EXPECT_TRUE(links.linked(0));
  EXPECT_FALSE(links.linked(1));
  EXPECT_FALSE(links.intact(1, bonds.neighbor.data()));
}

TEST(FaceLinks, RejectsPairsOutsideTheFamilies) {
  const BondLists bonds = bond_lists({{1}, {0}});
  EXPECT_THROW(FaceLinks({{0, 2}}, bonds), std::invalid_argument);
  EXPECT_THROW(FaceLinks({{-1, 0}}, bonds), std::invalid_argument);
}

}  // namespace
}  // namespace pd
