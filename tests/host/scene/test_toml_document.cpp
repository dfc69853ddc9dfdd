// A scene file's text as a TOML document (host/scene/toml_document.h): the characters toml++ 3.3
// cannot classify come back as written, syntax errors name the line and column, and the private-use
// characters that stand in for others are refused.
#include <gtest/gtest.h>

#include <string>

#include "host/scene/scene.h"
#include "host/scene/toml_document.h"

namespace pd {
namespace {

TEST(TomlDocument, ParsesPlainText) {
  const toml::table t = parse_toml_document("[simulation]\ndt = 1e-7\n", "s.toml");
  EXPECT_EQ(t["simulation"]["dt"].value<double>(), 1e-7);
}

TEST(TomlDocument, CharactersTomlCannotClassifyComeBackAsWritten) {
  // U+00E9 and U+0416 fall in the range toml++ 3.3's whitespace table does not handle; U+3042 not.
  const std::string text =
      "\"cl\xc3\xa9\" = \"caf\xc3\xa9 \xd0\x96\"\n[\"t\xc3\xa9\"]\nk = [\"\xe3\x81\x82\"]\n";
  const toml::table t = parse_toml_document(text, "s.toml");
  EXPECT_EQ(t["cl\xc3\xa9"].value<std::string>(), "caf\xc3\xa9 \xd0\x96");
  EXPECT_EQ(t["t\xc3\xa9"]["k"][0].value<std::string>(), "\xe3\x81\x82");
}

TEST(TomlDocument, ASyntaxErrorNamesTheLineAndColumn) {
  try {
    parse_toml_document("a = 1\nb = \xc3\xa9\n", "s.toml");
    ADD_FAILURE() << "a bare non-ASCII value accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file().rfind("s.toml:2:", 0), 0u) << e.file();
    const std::string m = e.what();
    EXPECT_NE(m.find("TOML syntax error"), std::string::npos) << m;
    EXPECT_EQ(m.find("\xf3\xb0"), std::string::npos) << "a stand-in character left in the message: " << m;
  }
}

TEST(TomlDocument, PrivateUseStandInsAreRefused) {
  try {
    parse_toml_document("description = \"\xf3\xb0\x83\xa9 \xc3\xa9\"\n", "s.toml");
    ADD_FAILURE() << "a stand-in character accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "s.toml");
    EXPECT_NE(std::string(e.what()).find("private-use"), std::string::npos) << e.what();
  }
  // Alone (nothing else shifted) it is an ordinary character.
  const toml::table t = parse_toml_document("description = \"\xf3\xb0\x83\xa9\"\n", "s.toml");
  EXPECT_EQ(t["description"].value<std::string>(), "\xf3\xb0\x83\xa9");
}

}  // namespace
}  // namespace pd
