// The JSON writer: valid documents whatever the text and numbers handed to it.
#include "ccomp/util/json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ccomp::util {
namespace {

TEST(JsonWriter, SeparatesMembersAndNestsObjectsAndArrays) {
  JsonWriter j;
  j.begin_object().field("a", 1).key("b").begin_array().value(1.5).value("x").null().end_array();
  j.key("c").begin_object().field("d", true).end_object().end_object();
  EXPECT_EQ(j.text(), "{\"a\": 1, \"b\": [1.5, \"x\", null], \"c\": {\"d\": true}}\n");
}

TEST(JsonWriter, NumbersThatAreNotFiniteAreNull) {
  JsonWriter j;
  j.begin_array().value(std::nan("")).value(std::numeric_limits<double>::infinity()).value(-0.25).end_array();
  EXPECT_EQ(j.text(), "[null, null, -0.25]\n");
}

TEST(JsonQuoted, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(json_quoted("a\"b\\c\nd\te"), "\"a\\\"b\\\\c\\nd\\u0009e\"");
}

TEST(JsonQuoted, KeepsUtf8AndTurnsEveryOtherByteIntoTheReplacementCharacter) {
  EXPECT_EQ(json_quoted("caf\xc3\xa9 \xe2\x82\xac"), "\"caf\xc3\xa9 \xe2\x82\xac\"");  // UTF-8 as it is
  // A Latin-1 e-acute is not shown as U+00E9: "caf\u00e9" is another file name.
  EXPECT_EQ(json_quoted("caf\xe9"), "\"caf\\ufffd\"");
  EXPECT_EQ(json_quoted("\xc3"), "\"\\ufffd\"");                          // a sequence cut short
  EXPECT_EQ(json_quoted("\xc0\xaf"), "\"\\ufffd\\ufffd\"");              // an overlong form
  EXPECT_EQ(json_quoted("\xe0\x80\xaf"), "\"\\ufffd\\ufffd\\ufffd\"");  // an overlong form of 3 bytes
  EXPECT_EQ(json_quoted("\xed\xa0\x80"), "\"\\ufffd\\ufffd\\ufffd\"");  // a UTF-16 surrogate
  EXPECT_EQ(json_quoted("\xf4\x90\x80\x80"), "\"\\ufffd\\ufffd\\ufffd\\ufffd\"");  // past U+10FFFF
}

}  // namespace
}  // namespace ccomp::util
