#include <string>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/poses/pose_io.h"

namespace rove {
namespace {

using detail::parse_bracketed;

TEST(ParseBracketed, AcceptsMrptForms) {
  EXPECT_EQ(parse_bracketed("[1 2 3]", {"a", "b", "c"}, "T"), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(parse_bracketed(" \t[ -1.5e2,+2 , 3.25 ]\r\n", {"a", "b", "c"}, "T"),
            (std::vector<double>{-150, 2, 3.25}));
  EXPECT_EQ(parse_bracketed("[1 2 30deg]", {"x", "y", "phi_deg"}, "T"),
            (std::vector<double>{1, 2, 30}));
  EXPECT_EQ(parse_bracketed("[]", {}, "T"), std::vector<double>{});
}

ParseError::Location location_of(std::string_view text) {
  try {
    (void)parse_bracketed(text, {"x", "y", "phi_deg"}, "Pose2");
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("Pose2"), std::string::npos) << e.what();
    return e.location();
  }
  ADD_FAILURE() << "no ParseError for \"" << text << "\"";
  return {};
}

TEST(ParseBracketed, ReportsFieldAndOffset) {
  auto loc = location_of("[1 2]");
  EXPECT_EQ(loc.field, "phi_deg");
  EXPECT_EQ(loc.source, "<string>");
  loc = location_of("[1 2q 3]");
  EXPECT_EQ(loc.field, "y");
  EXPECT_EQ(loc.offset, 4u);
  loc = location_of("[1 2 3 4]");
  EXPECT_EQ(loc.field, "phi_deg");
  EXPECT_EQ(loc.offset, 7u);
  loc = location_of("  1 2 3]");
  EXPECT_EQ(loc.field, "x");
  EXPECT_EQ(loc.offset, 2u);
  loc = location_of("[1 2 3");
  EXPECT_EQ(loc.field, "x");
  loc = location_of("[1 2deg 3]");
  EXPECT_EQ(loc.field, "y");
  loc = location_of("[1 2 3degx]");
  EXPECT_EQ(loc.field, "phi_deg");
  loc = location_of("[1 2 1e999]");
  EXPECT_EQ(loc.field, "phi_deg");
  loc = location_of("[1 -inf 3]");
  EXPECT_EQ(loc.field, "y");
  loc = location_of("[1 2 NaN]");
  EXPECT_EQ(loc.field, "phi_deg");
  loc = location_of("[1;2;3]");
  EXPECT_EQ(loc.field, "x");
  loc = location_of("[1 2 ]3]");
  EXPECT_EQ(loc.field, "phi_deg");
}

}  // namespace
}  // namespace rove
