// fragments.csv (host/fragments/fragment_log.h): one row per frame with the piece count, the
// singles and their mass share, the heaviest piece, the size histogram (its last bin open) and the
// free particles' mass share.
#include "host/fragments/fragment_log.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "tests/support/temp_dir.h"

namespace pd {
namespace {

using testing::read_all;

class FragmentLogTest : public testing::TempDirTest {};

// The fields of line `k` (0: the header).
std::vector<std::string> fields(const std::string& text, size_t k) {
  std::istringstream in(text);
  std::string line;
  for (size_t i = 0; i <= k; ++i) std::getline(in, line);
  std::vector<std::string> out;
  std::istringstream cells(line);
  for (std::string cell; std::getline(cells, cell, ',');) out.push_back(cell);
  return out;
}

TEST_F(FragmentLogTest, RowsHoldCountsSharesAndTheHistogram) {
  // Pieces of 1, 1, 2 and 4 particles of 1 kg each, and one of 2^25 particles (beyond the last
  // bin's lower bound), with the masses as component_stats gives them.
  ComponentStats s;
  s.count = 5;
  s.singles = 2;
  s.largest = 1 << 25;
  s.histogram.assign(26, 0);
  s.histogram[0] = 2;
  s.histogram[1] = 1;
  s.histogram[2] = 1;
  s.histogram[25] = 1;
  s.mass = 10;
  s.single_mass = 2;
  s.largest_mass = 4;
  s.free_counted = true;
  s.free_mass = 1;
  FragmentLog log(path("fragments.csv"));
  log.add(3, 300, 0.25, s);
  const std::string text = read_all(path("fragments.csv"));
  EXPECT_EQ(text, log.text());
  const std::vector<std::string> head = fields(text, 0), row = fields(text, 1);
  ASSERT_EQ(head.size(), 9u + kFragmentLogBins);
  ASSERT_EQ(row.size(), head.size());
  EXPECT_EQ(head[8], "n_1");
  EXPECT_EQ(head[9], "n_2_3");
  EXPECT_EQ(head[7 + kFragmentLogBins], "n_8388608_up");
  EXPECT_EQ(head.back(), "free_mass_share");
  EXPECT_EQ(row[0], "3");
  EXPECT_EQ(row[3], "5");
  EXPECT_EQ(row[4], "2");
  EXPECT_EQ(row[5], "0.2");  // 2 of 10 kg in singles
  EXPECT_EQ(row[6], "0.4");
  EXPECT_EQ(row[8], "2");
  EXPECT_EQ(row[9], "1");
  EXPECT_EQ(row[10], "1");
  EXPECT_EQ(row[7 + kFragmentLogBins], "1");  // the 2^25 piece, in the open bin
  EXPECT_EQ(row.back(), "0.1");               // 1 of 10 kg without an intact bond
}

TEST_F(FragmentLogTest, ARestoredLogGoesOn) {
  FragmentLog first(path("fragments.csv"));
  ComponentStats s;
  s.count = 1;
  s.histogram = {0, 0, 1};
  first.add(0, 0, 0.0, s);
  FragmentLog resumed(path("fragments.csv"));
  resumed.restore(first.text());
  resumed.add(1, 10, 0.5, s);
  EXPECT_EQ(fields(read_all(path("fragments.csv")), 2)[0], "1");
  EXPECT_EQ(fields(read_all(path("fragments.csv")), 1)[0], "0");
}

// A checkpoint written before the free particles' column: its header and rows get the column
// (empty in the old rows), and the run goes on with it.
TEST_F(FragmentLogTest, AnOlderCheckpointsLogGetsTheFreeColumn) {
  FragmentLog now(path("now.csv"));
  const std::string header = now.text();
  const std::string old_header = header.substr(0, header.rfind(",free_mass_share")) + "\n";
  std::string row = "0,0,0,1,0,0,1,8";
  for (int b = 0; b < kFragmentLogBins; ++b) row += b == 3 ? ",1" : ",0";
  FragmentLog resumed(path("fragments.csv"));
  resumed.restore(old_header + row + "\n");
  ComponentStats s;
  s.count = 1;
  s.histogram = {0, 0, 0, 1};
  s.mass = 2;
  s.largest_mass = 2;
  s.largest = 8;
  s.free_counted = true;
  resumed.add(1, 10, 0.5, s);
  const std::string text = read_all(path("fragments.csv"));
  EXPECT_EQ(text.substr(0, header.size()), header);
  EXPECT_EQ(fields(text, 1).size(), fields(text, 0).size() - 1);  // (an empty last cell)
  EXPECT_EQ(text.substr(header.size(), row.size() + 2), row + ",\n");
  EXPECT_EQ(fields(text, 2).size(), fields(text, 0).size());
  EXPECT_EQ(fields(text, 2).back(), "0");
}

}  // namespace
}  // namespace pd
