// The one reader of typed lengths and angles: units converted, and a bare number that cannot
// be meant in the place's unit refused with the reading it suggests.
#include "ccomp/model/quantity_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ccomp/error.hpp"
#include "ccomp/util/nearest_name.hpp"

namespace ccomp::model {
namespace {

struct Read {
  const char* text;
  QuantityRule (*rule)();
  double expected;  ///< in the rule's unit
};

class QuantityReads : public testing::TestWithParam<Read> {};

TEST_P(QuantityReads, InThePlacesUnit) {
  const Read& c = GetParam();
  EXPECT_NEAR(read_quantity(c.text, c.rule(), "--x"), c.expected, 1e-12 * std::max(1.0, std::abs(c.expected)))
      << c.text;
}

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

INSTANTIATE_TEST_SUITE_P(
    Units, QuantityReads,
    testing::Values(Read{"1um", rules::tolerance, 0.001}, Read{"0.001mm", rules::tolerance, 0.001},
                    Read{"0.001 mm", rules::tolerance, 0.001}, Read{"0.0001in", rules::tolerance, 0.00254},
                    Read{"500nm", rules::tolerance, 0.0005}, Read{"0.01", rules::tolerance, 0.01},
                    Read{"2mm", rules::tolerance, 2.0},  // written with its unit: meant
                    Read{"-250", rules::position, -250.0}, Read{"+0.3m", rules::position, 300.0},
                    Read{"-10in", rules::position, -254.0}, Read{"90", rules::angle, 90.0},
                    Read{"0.01deg", rules::angle, 0.01}, Read{"5urad", rules::angle, 5e-6 * kDegPerRad},
                    Read{"30arcsec", rules::angle, 30.0 / 3600.0}, Read{"0.5", rules::tool_length, 0.5},
                    Read{"0.2", rules::noise, 0.2}, Read{"0.0002mm", rules::noise, 0.2},
                    Read{"15", rules::rotary_step, 15.0}, Read{"2.5", rules::linear_step, 2.5}));

struct Refusal {
  const char* text;
  QuantityRule (*rule)();
  const char* says;
};

class QuantityRefusals : public testing::TestWithParam<Refusal> {};

TEST_P(QuantityRefusals, AreUsageErrorsThatSayWhy) {
  const Refusal& c = GetParam();
  try {
    (void)read_quantity(c.text, c.rule(), "--tolerance " + std::string(c.text));
    ADD_FAILURE() << c.text << " was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_NE(e.message().find(c.says), std::string::npos) << e.message();
    EXPECT_TRUE(e.message().starts_with("--tolerance " + std::string(c.text))) << e.message();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Units, QuantityRefusals,
    testing::Values(
        // A bare number that would be micrometres meant as mm, with the reading that fits.
        Refusal{"1", rules::tolerance, "did you mean 1um?"}, Refusal{"5", rules::tolerance, "did you mean 5um?"},
        Refusal{"2.5", rules::tolerance, "not a plausible compensation tolerance (up to 0.1 mm)"},
        Refusal{"500", rules::tolerance, "did you mean 500nm?"},
        Refusal{"0.001", rules::linear_step, "not a plausible step (from 0.01 mm)"},
        Refusal{"0", rules::tolerance, "must be more than 0 mm"}, Refusal{"-1um", rules::tolerance, "more than 0"},
        Refusal{"5urad", rules::tolerance, "'urad' measures angle, but length belongs here"},
        Refusal{"1mm", rules::angle, "'mm' measures length, but angle belongs here"},
        Refusal{"1furlong", rules::tolerance, "unknown unit 'furlong'"},
        Refusal{"abc", rules::tolerance, "not a number"}, Refusal{"nan", rules::tolerance, "not a finite number"},
        Refusal{"1e300", rules::position, "beyond any machine"},
        Refusal{"1e400", rules::position, "beyond any machine"},
        Refusal{"500", rules::noise, "not a plausible reading noise"}));

TEST(QuantityReader, ABareNumberOutOfRangeWithNoFittingReadingSuggestsNone) {
  try {
    (void)read_quantity("1e6", rules::tolerance(), "--tolerance 1e6");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.message().find("did you mean"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("write the unit to mean it: 1e6mm"), std::string::npos) << e.message();
  }
}

TEST(NearestName, FindsTheNearWordAndNothingFar) {
  const std::vector<std::string_view> commands{"trace", "flatten", "predict", "verify", "fit", "check", "simulate"};
  EXPECT_EQ(util::nearest_name("chek", commands), "check");
  EXPECT_EQ(util::nearest_name("verfy", commands), "verify");
  EXPECT_EQ(util::nearest_name("simualte", commands), "simulate");
  EXPECT_EQ(util::nearest_name("part", commands), "");
  EXPECT_EQ(util::nearest_name("--tolerence", {"--tolerance", "--time", "--threads"}), "--tolerance");
  EXPECT_EQ(util::edit_distance("kitten", "sitting"), 3U);
  EXPECT_EQ(util::edit_distance("", "abc"), 3U);
}

}  // namespace
}  // namespace ccomp::model
