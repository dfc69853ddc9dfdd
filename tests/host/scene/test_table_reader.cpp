// The table reader (host/scene/table_reader.h): typed access to a TOML table whose every mistake
// is one SceneError naming the file, the key's dotted path and what is allowed.
#include <gtest/gtest.h>

#include <string>

#include "host/scene/table_reader.h"

namespace pd {
namespace {

const std::string kFile = "scene.toml";

// The message of the SceneError that `read` throws, or "no error".
template <class F>
std::string error_of(F&& read) {
  try {
    read();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), kFile);
    return e.key() + " | " + e.what();
  }
  return "no error";
}

TEST(TableReader, AnUnknownKeyIsNamedWithTheAllowedOnes) {
  const toml::table t = toml::parse("dt = 1\nstep = 2\n");
  const std::string m = error_of([&] { TableReader(t, "simulation", kFile, {"dt", "steps"}); });
  EXPECT_EQ(m, "simulation.step | scene.toml: simulation.step: unknown key (allowed: dt, steps)");
}

TEST(TableReader, NumbersTakeIntegersAndKeepTheirBounds) {
  const toml::table t = toml::parse("a = 2\nb = 1.0\nc = \"x\"\nd = nan\n");
  const TableReader r(t, "m", kFile, {"a", "b", "c", "d"});
  double v = -1;
  EXPECT_TRUE(r.number("a", v, greater_than(0)));
  EXPECT_EQ(v, 2.0);
  EXPECT_FALSE(r.number("absent", v));
  EXPECT_EQ(v, 2.0) << "an absent key leaves the default";
  EXPECT_EQ(error_of([&] { r.number("b", v, in_open(0, 1)); }),
            "m.b | scene.toml: m.b: 1 is out of range (allowed: a number in (0, 1))");
  EXPECT_EQ(error_of([&] { r.number("c", v); }),
            "m.c | scene.toml: m.c: expected a number, got a string (allowed: a finite number)");
  EXPECT_EQ(error_of([&] { r.number("d", v, at_least(0)); }),
            "m.d | scene.toml: m.d: nan is not a finite number (allowed: a number >= 0)");
  EXPECT_EQ(error_of([&] { r.number("absent", v, in_closed(0, 1), Presence::required); }),
            "m.absent | scene.toml: m.absent: missing required key (allowed: a number in [0, 1])");
}

TEST(TableReader, IntegersBooleansAndStrings) {
  const toml::table t = toml::parse("n = 12\nf = 1.5\nb = true\ns = \"cubes\"\n");
  const TableReader r(t, "", kFile, {"n", "f", "b", "s"});
  int64_t n = 0;
  EXPECT_TRUE(r.integer("n", n, 1, 100));
  EXPECT_EQ(n, 12);
  EXPECT_EQ(error_of([&] { r.integer("n", n, 20); }),
            "n | scene.toml: n: 12 is out of range (allowed: an integer >= 20)");
  EXPECT_EQ(error_of([&] { r.integer("f", n, 0, 9); }),
            "f | scene.toml: f: expected an integer, got a float (allowed: an integer from 0 to 9)");
  bool b = false;
  EXPECT_TRUE(r.boolean("b", b));
  EXPECT_TRUE(b);
  std::string s;
  EXPECT_TRUE(r.string("s", s, {"cubes", "tets"}));
  EXPECT_EQ(s, "cubes");
  EXPECT_EQ(error_of([&] {
              r.string("s", s, {"grid", "tets"});
            }),
            "s | scene.toml: s: unsupported value \"cubes\" (allowed: \"grid\", \"tets\")");
}

TEST(TableReader, VectorsAndKeyframesNameTheElement) {
  const toml::table t = toml::parse(
      "v = [1, 2, 3]\nw = [1, \"y\", 3]\nk = [[0, 0, 0, 0], [1, 1, 0, 0]]\nbad = [[0, 0, 0, 0], [0, 1, 0, "
      "0]]\n");
  const TableReader r(t, "body", kFile, {"v", "w", "k", "bad"});
  Vec3d v{};
  EXPECT_TRUE(r.vec3("v", v));
  EXPECT_EQ(v[2], 3.0);
  EXPECT_EQ(error_of([&] { r.vec3("w", v); }),
            "body.w[1] | scene.toml: body.w[1]: expected a number, got a string (allowed: a finite number)");
  std::vector<SceneKeyframe> frames;
  EXPECT_TRUE(r.keyframes("k", frames));
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1][1], 1.0);
  EXPECT_NE(error_of([&] { r.keyframes("bad", frames); }).find("body.bad[1][0]: time 0 does not follow 0"),
            std::string::npos);
}

TEST(TableReader, SubTablesCarryTheirPath) {
  const toml::table t = toml::parse("[materials.glass]\ndensity = 2\n[[bodies]]\nname = 3\n");
  const TableReader root(t, "", kFile, {"materials", "bodies"});
  const auto materials = root.named_tables("materials", {"density"});
  ASSERT_EQ(materials.size(), 1u);
  EXPECT_EQ(materials[0].first, "glass");
  EXPECT_EQ(materials[0].second.path("density"), "materials.glass.density");
  const auto bodies = root.table_array("bodies", {"name"});
  ASSERT_EQ(bodies.size(), 1u);
  std::string name;
  EXPECT_EQ(
      error_of([&] { bodies[0].string("name", name); }),
      "bodies[0].name | scene.toml: bodies[0].name: expected a string, got an integer (allowed: a string)");
  EXPECT_EQ(root.table("absent", {}).path(""), "absent") << "an absent table reads as empty";
}

TEST(TableReader, MessagesStayOnOneLine) {
  EXPECT_EQ(one_line("a\nb\x7f"), "a\\x0ab\\x7f");
  EXPECT_EQ(in_quotes("x\ty"), "\"x\\x09y\"");
  EXPECT_EQ(join({"a", "b"}, true), "\"a\", \"b\"");
  // Numbers in their shortest form that reads back as the same double.
  EXPECT_EQ(number_text(0.5), "0.5");
  EXPECT_EQ(number_text(1e8), "1e+08");
  EXPECT_EQ(number_text(0.99999999), "0.99999999");
  EXPECT_EQ(number_text(0.1), "0.1");
}

}  // namespace
}  // namespace pd
