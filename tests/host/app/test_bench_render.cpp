// `perifrac bench-render` on small synthetic scenes (tets, cubes, turned cubes; with the two-level
// prototype): runs on the CPU, prints its figures and writes a results file with them; bad options
// are refused.
#include "host/app/bench_render.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace pd {
namespace {

namespace fs = std::filesystem;

TEST(BenchRender, SmallRunWritesItsResults) {
  const fs::path out = fs::path(::testing::TempDir()) / ("perifrac_bench_render_" + std::to_string(getpid()));
  fs::remove_all(out);
  for (const char* scene : {"slab", "cubes", "turned-cubes"}) {
    RenderBenchOptions o;
    o.scene = scene;
    o.count = 3000;
    o.width = 64;
    o.height = 48;
    o.backend = "cpu";
    o.repeat = 1;
    o.fragments = 4;
    o.out = out.string();
    ASSERT_EQ(bench_render_command(o), 0) << scene;
  }
  int files = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    ++files;
    std::ifstream in(e.path());
    std::stringstream text;
    text << in.rdbuf();
    for (const char* key :
         {"\"device\"", "\"date\"", "\"git\"", "\"build_seconds\"", "\"serial_build_seconds\"",
          "\"primary_rays_per_s\"", "\"all_rays_per_s\"", "\"tests_per_ray\"", "\"two_level\""})
      EXPECT_NE(text.str().find(key), std::string::npos) << e.path() << " lacks " << key;
#if defined(PERIFRAC_HAS_EMBREE)
    EXPECT_NE(text.str().find("\"embree\""), std::string::npos) << e.path();
    EXPECT_NE(text.str().find("\"depth_agreement\": 1"), std::string::npos) << e.path();
#endif
  }
  EXPECT_EQ(files, 3);
  fs::remove_all(out);
}

TEST(BenchRender, RefusesBadOptions) {
  RenderBenchOptions o;
  o.scene = "teapot";
  EXPECT_THROW(bench_render_command(o), std::invalid_argument);
  o.scene = "slab";
  o.repeat = 0;
  EXPECT_THROW(bench_render_command(o), std::invalid_argument);
}

}  // namespace
}  // namespace pd
