#include "rove/core/json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rove/core/error.h"

namespace {

TEST(JsonQuote, EscapesPerRfc8259) {
  EXPECT_EQ(rove::json_quote("a\"b\\c"), R"("a\"b\\c")");
  EXPECT_EQ(rove::json_quote("l1\nl2\t"), R"("l1\nl2\t")");
  EXPECT_EQ(rove::json_quote(std::string("\x01", 1)), R"("\u0001")");
  EXPECT_EQ(rove::json_quote("caf\xc3\xa9 \xe2\x82\xac"), "\"caf\xc3\xa9 \xe2\x82\xac\"");
}

TEST(JsonQuote, InvalidUtf8BecomesReplacementCharacter) {
  // A non-UTF-8 path (Latin-1 é) must still give valid JSON.
  EXPECT_EQ(rove::json_quote("caf\xe9.rawlog"), "\"caf\xef\xbf\xbd.rawlog\"");
  EXPECT_EQ(rove::json_quote("\xed\xa0\x80"), "\"\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd\"");  // surrogate
  EXPECT_EQ(rove::json_quote("x\xf0\x9f"), "\"x\xef\xbf\xbd\xef\xbf\xbd\"");               // truncated
}

TEST(JsonWriter, WritesNestedDocuments) {
  rove::JsonWriter j(0);
  j.begin_object();
  j.key("ok").value(true);
  j.key("n").value(3);
  j.key("x").value(0.5);
  j.key("nan").value(std::numeric_limits<double>::quiet_NaN());
  j.key("list").begin_array().value("a").value(std::uint64_t{7}).end_array();
  j.key("empty").begin_object().end_object();
  j.end_object();
  EXPECT_EQ(j.str(), R"({"ok":true,"n":3,"x":0.5,"nan":null,"list":["a",7],"empty":{}})");
}

TEST(JsonWriter, IndentedOutputEndsWithNewline) {
  rove::JsonWriter j;
  j.begin_object().key("a").begin_array().value(1).end_array().end_object();
  EXPECT_EQ(j.str(), "{\n  \"a\": [\n    1\n  ]\n}\n");
}

TEST(JsonWriter, DoublesRoundTrip) {
  rove::JsonWriter j(0);
  const double v = 0.1 + 0.2;
  j.begin_array().value(v).end_array();
  const std::string s = j.str();
  EXPECT_EQ(std::stod(s.substr(1, s.size() - 2)), v);
}

TEST(JsonWriter, MisuseIsRefused) {
  rove::JsonWriter a;
  a.begin_object();
  EXPECT_THROW(a.value(1), rove::InvalidArgument);  // value without key
  EXPECT_THROW(a.end_array(), rove::InvalidArgument);
  EXPECT_THROW((void)a.str(), rove::InvalidArgument);  // still open
  rove::JsonWriter b;
  b.begin_array();
  EXPECT_THROW(b.key("k"), rove::InvalidArgument);
}

}  // namespace
