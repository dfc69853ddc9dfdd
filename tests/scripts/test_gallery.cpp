// scripts/gallery.sh --encode: clips made from frames rendered elsewhere, linked from the index,
// with the index's header and hand-written sections kept, and the same index when run twice.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/io/png_file.h"
#include "tests/support/temp_dir.h"

namespace pd {
namespace {

class GalleryScript : public testing::TempDirTest {};

const char* kIndex =
    "# Gallery\n\nMade by hand on a GPU machine.\n\n"
    "| entry | figure | scene and overrides | particles | bonds | ms per step | device | still |\n"
    "| --- | --- | --- | --- | --- | --- | --- | --- |\n"
    "| glass_plate | Levine Fig. 2 | glass_plate_projectile.toml | 131072 | 1 | 0.25 | gpu | "
    "![glass_plate](glass_plate.png) |\n"
    "| vase | Levine Fig. 1 | vase_drop.toml | 149118 | 1 | 0.39 | gpu | ![vase](vase.png) |\n"
    "\n## Against the papers\n\nWhat the stills show.\n";

TEST_F(GalleryScript, EncodeMakesTheClipsAndLinksThem) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) GTEST_SKIP() << "no ffmpeg on PATH";
  const std::string out = path("out"), docs = path("docs");
  std::filesystem::create_directories(out + "/glass_plate/render");
  std::filesystem::create_directories(docs);
  for (int f = 0; f < 4; ++f) {
    ImageRGB8 image{32, 16, std::vector<uint8_t>(32 * 16 * 3)};
    for (size_t k = 0; k < image.rgb.size(); ++k) image.rgb[k] = uint8_t(k * (f + 1));
    write_png(out + "/glass_plate/render/frame_0000" + std::to_string(f) + ".png", image);
  }
  std::ofstream(docs + "/README.md") << kIndex;
  const std::string command = "PERIFRAC_BIN=" PERIFRAC_BINARY " " PERIFRAC_SOURCE_DIR
                              "/scripts/gallery.sh --encode --out " +
                              out + " --docs " + docs + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  EXPECT_GT(std::filesystem::file_size(docs + "/glass_plate.mp4"), 0u);
  EXPECT_FALSE(std::filesystem::exists(docs + "/vase.mp4"));  // no frames: no clip
  std::string expected = kIndex;
  const std::string still = "![glass_plate](glass_plate.png)";
  expected.insert(expected.find(still) + still.size(), " [clip](glass_plate.mp4)");
  EXPECT_EQ(testing::read_all(docs + "/README.md"), expected);

  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(testing::read_all(docs + "/README.md"), expected);
}

}  // namespace
}  // namespace pd
