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
  EXPECT_EQ(e.message(),
            "a reading the model needs was not given: --sensor spindle=VALUE (term EZZ depends on sensor 'spindle')");
  EXPECT_EQ(conditions_for(thermal_vmc(), {{"spindle", 30.0}}, 0.0).temperatures[0], 30.0);
}

/// Three sensors and a warm-up, the terms listed in another order than the sensors.
model::MachineModel three_sensor_machine() {
  std::string chain = kVmcChain;
  chain.replace(chain.find("sensors: [spindle]"), 18, "sensors: [bed, column, spindle]");
  return model::parse_machine_model(chain + R"(terms:
  - {name: EZZ, variable: T_spindle, form: thermal, coefficient: 3, unit: um}
  - {name: EXX, variable: T_bed, form: thermal, coefficient: 2, unit: um}
  - {name: EYY, variable: T_column, form: thermal, coefficient: 1, unit: um}
  - {name: EXY, variable: t, form: warmup, amplitude: 5, time_constant: 1800, unit: um}
)",
                                    "three.yaml");
}

// Every missing reading in one refusal, in the model's sensor order (not the terms'), the
// time last: one run tells the user the whole command line, and the same each time.
TEST(Conditions, NamesEveryMissingReadingInOneRefusal) {
  const model::MachineModel m = three_sensor_machine();
  const Error all = error_of([&] { (void)conditions_for(m, {}, std::nullopt); }, "every reading");
  EXPECT_EQ(all.kind(), ErrorKind::usage);
  EXPECT_EQ(all.message(),
            "4 readings the model needs were not given:\n"
            "  --sensor bed=VALUE (term EXX depends on sensor 'bed')\n"
            "  --sensor column=VALUE (term EYY depends on sensor 'column')\n"
            "  --sensor spindle=VALUE (term EZZ depends on sensor 'spindle')\n"
            "  --time SECONDS (term EXY depends on the time since the warm-up started)");
  const Error again = error_of([&] { (void)conditions_for(m, {}, std::nullopt); }, "every reading");
  EXPECT_EQ(again.message(), all.message());
  const Error some = error_of([&] { (void)conditions_for(m, {{"column", 20.0}}, 0.0); }, "two readings");
  EXPECT_EQ(some.message(),
            "2 readings the model needs were not given:\n"
            "  --sensor bed=VALUE (term EXX depends on sensor 'bed')\n"
            "  --sensor spindle=VALUE (term EZZ depends on sensor 'spindle')");
  EXPECT_NO_THROW((void)conditions_for(m, {{"spindle", 21.0}, {"column", 20.0}, {"bed", 22.0}}, 0.0));
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
