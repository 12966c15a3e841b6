// The conditions from the command line's readings: every sensor mistake is refused as a
// usage error (exit 2) that names what to fix.
#include "ccomp/model/conditions.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"
#include "sample_models.hpp"

namespace ccomp::test {
namespace {

using model::conditions_for;
using model::parse_sensor_reading;

/// The 3-axis chain (sensor "spindle") with a thermal term on it.
model::MachineModel thermal_vmc() {
  return model::parse_machine_model(std::string(kVmcChain) + R"(terms:
  - {name: EZZ, variable: T_spindle, form: thermal, coefficient: 3, unit: um}
)",
                                    "vmc.yaml");
}

/// The 5-axis chain (sensors "bed" and "spindle") with no thermal terms.
model::MachineModel plain_hmc() {
  return model::parse_machine_model(kHmcChain, "hmc.yaml");
}

/// The 3-axis chain with a warm-up term over the time.
model::MachineModel warming_vmc() {
  return model::parse_machine_model(std::string(kVmcChain) + R"(terms:
  - {name: EZZ, variable: t, form: warmup, amplitude: 5, time_constant: 1800, unit: um}
)",
                                    "vmc.yaml");
}

TEST(Conditions, RefusesAWarmUpTermWithoutTheTime) {
  // As a thermal term without its sensor: t = 0 would leave the warm-up out in silence.
  const Error e = error_of([] { (void)conditions_for(warming_vmc(), {}, std::nullopt); }, "--time");
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_NE(e.message().find("EZZ"), std::string::npos) << e.message();
  EXPECT_EQ(conditions_for(warming_vmc(), {}, 0.0).time, 0.0);  // given, even as 0, it is taken
  EXPECT_EQ(conditions_for(plain_hmc(), {}, std::nullopt).time, 0.0);  // no term over the time: none needed
}

TEST(Conditions, ParsesAReading) {
  EXPECT_EQ(parse_sensor_reading("spindle=31.5"), (model::SensorReading{"spindle", 31.5}));
  EXPECT_EQ(parse_sensor_reading("bed=-4e1"), (model::SensorReading{"bed", -40.0}));
}

TEST(Conditions, RefusesAReadingThatIsNotNameEqualsANumber) {
  for (const char* text : {"spindle", "=30", "spindle=", "spindle=30x", "spindle= 30", "spindle=inf", "spindle=nan",
                           "spindle=1e999", "spindle=thirty"}) {
    const Error e = error_of([&] { (void)parse_sensor_reading(text); }, text);
    EXPECT_EQ(e.kind(), ErrorKind::usage) << text;
    EXPECT_EQ(e.message(), fmt::format("--sensor takes NAME=DEGC, not '{}'", text));
  }
}

TEST(Conditions, PutsReadingsInTheModelsSensorOrder) {
  const model::Conditions c = conditions_for(plain_hmc(), {{"spindle", 31.0}, {"bed", 22.0}}, 3600.0);
  EXPECT_EQ(c.time, 3600.0);
  ASSERT_EQ(c.temperatures.size(), 2U);
  EXPECT_EQ(c.temperatures[0], 22.0);
  EXPECT_EQ(c.temperatures[1], 31.0);
}

TEST(Conditions, LeavesASensorNoTermNeedsUnread) {
  const model::Conditions c = conditions_for(plain_hmc(), {{"bed", 22.0}}, 0.0);
  EXPECT_EQ(c.temperatures[0], 22.0);
  EXPECT_TRUE(std::isnan(c.temperatures[1]));
}

TEST(Conditions, RefusesASensorTheMachineLacks) {
  const Error e = error_of([] { (void)conditions_for(plain_hmc(), {{"nozzle", 30.0}}, 0.0); }, "nozzle");
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_EQ(e.message(), "--sensor nozzle: machine 'test-hmc' has no sensor of that name (its sensors: bed, spindle)");
}

TEST(Conditions, RefusesASensorOfAMachineWithoutSensors) {
  model::MachineModel m = plain_hmc();
  m.sensors.clear();
  const Error e = error_of([&] { (void)conditions_for(m, {{"bed", 30.0}}, 0.0); }, "bed");
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_EQ(e.message(), "--sensor bed: machine 'test-hmc' has no sensor of that name (it has no sensors)");
}

TEST(Conditions, RefusesASensorReadTwice) {
  const Error e = error_of([] { (void)conditions_for(plain_hmc(), {{"bed", 20.0}, {"bed", 21.5}}, 0.0); }, "twice");
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_EQ(e.message(), "--sensor bed: read twice (20 and 21.5); give one reading");
}

TEST(Conditions, RefusesAMissingReadingATermNeeds) {
  const Error e = error_of([] { (void)conditions_for(thermal_vmc(), {}, 0.0); }, "no reading");
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_EQ(e.message(), "term EZZ depends on sensor 'spindle', and no reading was given: --sensor spindle=VALUE");
  EXPECT_EQ(conditions_for(thermal_vmc(), {{"spindle", 30.0}}, 0.0).temperatures[0], 30.0);
}

TEST(Conditions, RefusesATimeOrReadingThatIsNotFinite) {
  const double inf = std::numeric_limits<double>::infinity();
  const Error time = error_of([&] { (void)conditions_for(plain_hmc(), {}, inf); }, "time");
  EXPECT_EQ(time.kind(), ErrorKind::usage);
  EXPECT_EQ(time.message(), "the time must be finite, not inf");
  const Error reading = error_of([&] { (void)conditions_for(plain_hmc(), {{"bed", std::nan("")}}, 0.0); }, "NaN");
  EXPECT_EQ(reading.kind(), ErrorKind::usage);
  EXPECT_EQ(reading.message(), "sensor 'bed' must read a finite temperature, not nan");
}

}  // namespace
}  // namespace ccomp::test
