// The last guard before a table is printed: a value that is not a number never reaches a
// control's file (a NaN printed as '-nan' in LinuxCNC, Siemens and Heidenhain tables and
// rounded to 'P0' in Fanuc's), whatever sampled it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ccomp/controller/control_tables.hpp"
#include "ccomp/controller/isg_volume.hpp"
#include "ccomp/error.hpp"
#include "error_of.hpp"

namespace ccomp::controller {
namespace {

AxisTable table_with(double bad, std::size_t at) {
  AxisTable t;
  t.axis = 'X';
  // From 0 (Centroid's table starts at machine home; the others take any span).
  for (int k = 0; k <= 4; ++k) t.positions.push_back(2.0 * k);
  t.reference = 0.0;
  t.forward.assign(t.positions.size(), 0.001);
  t.reverse = t.forward;
  t.forward[at] = bad;
  return t;
}

class FiniteTables : public ::testing::TestWithParam<const ControlTable*> {};

TEST_P(FiniteTables, AValueThatIsNotANumberIsRefusedNamingItsPoint) {
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity()}) {
    WriteOptions o;
    const std::string written = write_table(*GetParam(), table_with(0.002, 3), o);  // the table itself is fine
    EXPECT_FALSE(written.empty());
    const Error e = test::error_of([&] { (void)write_table(*GetParam(), table_with(bad, 1), o); }, "written");
    EXPECT_EQ(e.kind(), ErrorKind::safety);
    EXPECT_NE(e.message().find("at X 2"), std::string::npos) << e.message();
  }
}

// Every control of the registry, so a new one is tested without being named here.
INSTANTIATE_TEST_SUITE_P(EveryControl, FiniteTables, ::testing::ValuesIn(control_tables()),
                         [](const ::testing::TestParamInfo<const ControlTable*>& p) {
                           return std::string(p.param->name);
                         });

TEST(FiniteTables, TheVolumetricTableRefusesAValueThatIsNotANumber) {
  VolumeTable t;
  for (std::size_t a = 0; a < 3; ++a) t.positions[a] = {0.0, 10.0};
  t.correction.assign(t.nodes(), Eigen::Vector3d::Zero());
  EXPECT_FALSE(write_isg_volume(t, "v.csv", {}).csv.empty());
  t.correction[t.index(1, 0, 1)].y() = std::numeric_limits<double>::quiet_NaN();
  const Error e = test::error_of([&] { (void)write_isg_volume(t, "v.csv", {}); }, "written");
  EXPECT_EQ(e.kind(), ErrorKind::safety);
  EXPECT_NE(e.message().find("X 10 Y 0 Z 10"), std::string::npos) << e.message();
}

}  // namespace
}  // namespace ccomp::controller
