// The axes as a type: letters and places, sets iterated in X..W order, arrays indexed by axis;
// and a model whose axis type its letter's program words contradict is refused.
#include "ccomp/axis.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "ccomp/error.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp {
namespace {

TEST(Axis, LettersAndPlacesGoBothWays) {
  for (const Axis a : kAllAxes) {
    EXPECT_EQ(axis_named(letter(a)), a) << letter(a);
    EXPECT_EQ(axis_at(index(a)), a) << letter(a);
    EXPECT_EQ(index_of_letter(letter(a)), index(a));
  }
  EXPECT_EQ(letter(Axis::B), 'B');
  EXPECT_EQ(index(Axis::U), 6U);
  for (const char c : {'x', 'Q', 'L', '\0', ' '}) EXPECT_FALSE(axis_named(c)) << int(c);
  EXPECT_FALSE(axis_at(kAxisCount));
  EXPECT_THROW((void)index_of_letter('Q'), std::bad_optional_access);
}

TEST(Axis, OnlyABAndCAreAnglesInPrograms) {
  std::string angular;
  for (std::size_t i = 0; i <= kAxisCount; ++i)
    if (angular_at(i)) angular += kAxisLetters[i];
  EXPECT_EQ(angular, "ABC");
}

TEST(AxisSet, HoldsEachAxisOnceAndIteratesInOrder) {
  AxisSet s{Axis::C, Axis::X, Axis::C};
  EXPECT_EQ(s.size(), 2U);
  EXPECT_EQ(s.letters(), "XC");
  s.insert_at(4);
  s.insert_at(kAxisCount);  // past W: no axis
  EXPECT_EQ(s.letters(), "XBC");
  EXPECT_TRUE(s.contains_at(4));
  EXPECT_FALSE(s.contains_at(kAxisCount));
  std::vector<Axis> seen(s.begin(), s.end());
  EXPECT_EQ(seen, (std::vector<Axis>{Axis::X, Axis::B, Axis::C}));
  s.erase(Axis::X);
  EXPECT_EQ(s.letters(), "BC");
  EXPECT_TRUE(AxisSet{}.empty());
  EXPECT_EQ(AxisSet{}.begin(), AxisSet{}.end());
}

TEST(AxisSet, UnionAndDifference) {
  const AxisSet ab{Axis::A, Axis::B}, bc{Axis::B, Axis::C};
  EXPECT_EQ((ab | bc).letters(), "ABC");
  EXPECT_EQ((ab - bc).letters(), "A");
  AxisSet s = ab;
  s -= ab;
  EXPECT_TRUE(s.empty());
  s |= bc;
  EXPECT_EQ(s, bc);
}

TEST(AxisArray, IndexedByAxisOrByPlace) {
  AxisArray<double> q{};
  q[Axis::B] = 30.0;
  EXPECT_EQ(q[4], 30.0);
  q[6] = 1.5;
  EXPECT_EQ(q[Axis::U], 1.5);
}

TEST(AxisType, AModelBuiltInCodeWithATypeItsLetterContradictsIsRefused) {
  model::MachineModel m;
  m.name = "m";
  m.path = "built.yaml";
  m.axes = {model::AxisSpec{'X'}, model::AxisSpec{'W', model::AxisType::rotary}};
  try {
    model::validate(m);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::model);
    EXPECT_NE(e.message().find("axis W: type rotary, but programs give W in lengths"), std::string::npos)
        << e.message();
  }
  m.axes[1] = model::AxisSpec{'C', model::AxisType::rotary};
  EXPECT_FALSE(model::type_contradiction(m.axes[1]));
}

}  // namespace
}  // namespace ccomp
