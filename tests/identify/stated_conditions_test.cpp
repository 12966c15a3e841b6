// What a test's files and options state beside its readings, sorted for ISO 230-2's report:
// the instrument, temperatures in degC, the uncertainty statement, and the rest as written.
#include "ccomp/identify/stated_conditions.hpp"

#include <gtest/gtest.h>

#include "ccomp/error.hpp"

namespace ccomp::identify {
namespace {

TEST(StatedConditions, SortsTheInstrumentTemperaturesAndUncertaintyFromTheRest) {
  const StatedConditions s = sort_stated({{"Machine", "HMC sample", "x.rtl"},
                                          {"Material temperature", "20.4", "x.rtl"},
                                          {"Air temp", "68.9 F", "x.rtl"},
                                          {"Laser", "XL-80 s/n 123", "x.rtl"},
                                          {"Expanded uncertainty", "U = 1.2 um (k = 2)", "x.rtl"},
                                          {"Date", "2026-11-28", "x.rtl"},
                                          {"Coolant temperature", "not measured", "x.rtl"}});
  ASSERT_TRUE(s.instrument.has_value());
  EXPECT_EQ(s.instrument->value, "XL-80 s/n 123");
  ASSERT_TRUE(s.uncertainty.has_value());
  EXPECT_EQ(s.uncertainty->value, "U = 1.2 um (k = 2)");
  ASSERT_EQ(s.temperatures.size(), 2U);
  EXPECT_EQ(s.temperatures[0].name, "Material temperature");
  EXPECT_DOUBLE_EQ(s.temperatures[0].degc, 20.4);
  EXPECT_NEAR(s.temperatures[1].degc, (68.9 - 32.0) * 5.0 / 9.0, 1e-12) << "a value in F is converted";
  // A temperature without a number is not a temperature the report can give: kept as written.
  ASSERT_EQ(s.others.size(), 3U);
  EXPECT_EQ(s.others[0].key, "Machine");
  EXPECT_EQ(s.others[2].value, "not measured");
}

TEST(StatedConditions, AnOptionStatedLaterTakesThePlaceOfTheFiles) {
  const StatedConditions s = sort_stated({{"Instrument", "from the file", "x.csv"},
                                          {"Air temperature", "20.9", "x.csv"},
                                          {"Instrument", "XL-80", "--instrument"},
                                          temperature_option("air=20.3")});
  EXPECT_EQ(s.instrument->value, "XL-80");
  ASSERT_EQ(s.temperatures.size(), 1U) << "the same temperature named again replaces it";
  EXPECT_DOUBLE_EQ(s.temperatures[0].degc, 20.3);
  EXPECT_EQ(s.temperatures[0].source, "--temperature");
}

TEST(StatedConditions, ATemperatureOptionIsANameAndDegreesCelsius) {
  EXPECT_EQ(temperature_option("material=20.1").key, "material temperature");
  EXPECT_EQ(temperature_option("machine temp=21").key, "machine temp");
  for (const char* bad : {"20.3", "air", "air=", "air=warm", "air=nan", "air=1e300", "=20", "air=20.3C"}) {
    try {
      (void)temperature_option(bad);
      ADD_FAILURE() << bad << " was taken";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::usage) << bad;
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace ccomp::identify
