// Units of the model file: conversions into mm, rad, s, degC, and refusals by dimension.
#include "ccomp/model/units.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "ccomp/error.hpp"

namespace ccomp::model {
namespace {

TEST(Units, ConvertToInternalUnits) {
  EXPECT_DOUBLE_EQ(parse_quantity("350 mm", kLength, "mm", "d"), 350.0);
  EXPECT_DOUBLE_EQ(parse_quantity("12 um", kLength, "mm", "e"), 0.012);
  EXPECT_DOUBLE_EQ(parse_quantity("0.5", kLength, "mm", "bound"), 0.5);
  EXPECT_DOUBLE_EQ(parse_quantity("1 in", kLength, "mm", "e"), 25.4);
  EXPECT_NEAR(parse_quantity("3 arcsec", kAngle, "rad", "e"), 3.0 * M_PI / 648000.0, 1e-18);
  EXPECT_NEAR(parse_quantity("-20 urad", kAngle, "rad", "e"), -20e-6, 1e-18);
  EXPECT_NEAR(parse_quantity("90 deg", kAngle, "rad", "e"), M_PI / 2, 1e-15);
  EXPECT_DOUBLE_EQ(parse_quantity("30 min", kTime, "s", "tau"), 1800.0);
  EXPECT_DOUBLE_EQ(parse_quantity("12 um/m", kDimensionless, "1", "strain"), 12e-6);
  EXPECT_DOUBLE_EQ(parse_quantity("1.5 um/degC", kLength / kTemperature, "mm/degC", "k"), 0.0015);
  EXPECT_DOUBLE_EQ(parse_quantity("11.5e-6 /degC", kTemperature.pow(-1), "1/degC", "alpha"), 11.5e-6);
  const auto u = parse_unit("um/mm^2");
  ASSERT_TRUE(u);
  EXPECT_DOUBLE_EQ(u->scale, 1e-3);
  EXPECT_TRUE(u->dimension == kLength.pow(-1));
}

TEST(Units, RefuseWrongDimensionUnknownUnitAndNaN) {
  auto message = [](const char* text, Dimension d) {
    try {
      (void)parse_quantity(text, d, "mm", "term EXX");
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::model);
      return e.message();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("3 urad", kLength), "term EXX: 'urad' measures angle, but length belongs here");
  EXPECT_EQ(message("3 um/degC", kLength),
            "term EXX: 'um/degC' measures length / temperature, but length belongs here");
  EXPECT_NE(message("3 furlong", kLength).find("unknown unit 'furlong'"), std::string::npos);
  EXPECT_NE(message("nan mm", kLength).find("not a number"), std::string::npos);
  EXPECT_NE(message("fast", kLength).find("not a number"), std::string::npos);
}

}  // namespace
}  // namespace ccomp::model
