#include "host/io/json_text.h"

#include <gtest/gtest.h>

namespace pd {
namespace {

TEST(JsonText, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(json_escape("NVIDIA H200"), "NVIDIA H200");
  EXPECT_EQ(json_escape("a \"b\" c\\d"), "a \\\"b\\\" c\\\\d");
  EXPECT_EQ(json_escape("line\nbreak\ttab\x01"), "line\\u000abreak\\u0009tab\\u0001");
  EXPECT_EQ(json_escape("caf\xc3\xa9"), "caf\xc3\xa9");  // UTF-8 passes through
  EXPECT_EQ(json_escape(""), "");
}

}  // namespace
}  // namespace pd
