// verify's search keeps the pieces near a point for the points after it: that must find
// what searching the whole window for every point finds, piece for piece, on the paths
// where a careless argument goes wrong: a steep helix crossing a line (an arc's distance
// moves faster than the point), a spiral, a path traced back over pieces finer than the
// point's step, a spring pass of as many pieces as the window ahead holds.
#include "compensate/path_search.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <utility>
#include <vector>

namespace ccomp::compensate {
namespace {

/// A path from a list of pieces, made available as the search asks (as verify's original
/// is read).
class ListPath {
 public:
  explicit ListPath(std::vector<Piece> pieces) : pieces_(std::move(pieces)) {}
  PieceWindow& window() { return window_; }
  std::size_t available(std::size_t end) {
    while (window_.end() < end && next_ < pieces_.size()) window_.append(pieces_[next_++]);
    return std::min(end, window_.end());
  }
  std::pair<double, std::uint32_t> rest_from(std::size_t i) {
    double length = 0.0;
    std::uint32_t line = 0;
    for (std::size_t k = std::max(i, window_.first()); k < pieces_.size(); ++k) {
      if (line == 0) line = pieces_[k].line;
      length += pieces_[k].length();
    }
    return {length, line};
  }

 private:
  std::vector<Piece> pieces_;
  std::size_t next_ = 0;
  PieceWindow window_;
};

Piece segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, std::uint32_t line) {
  Piece p;
  p.a = a, p.b = b, p.line = line;
  return p;
}

/// An arc about the Z axis through `centre`, counter-clockwise from angle a0 by `sweep`,
/// its radius going from r0 to r1 and rising by dw.
Piece arc(const Eigen::Vector3d& centre, double r0, double r1, double a0, double sweep, double dw, std::uint32_t line) {
  Piece p;
  p.arc = true, p.centre = centre, p.e1 = Eigen::Vector3d::UnitX(), p.e2 = Eigen::Vector3d::UnitY();
  p.n = Eigen::Vector3d::UnitZ();
  p.r0 = r0, p.r1 = r1, p.a0 = a0, p.sweep = sweep, p.dw = dw, p.line = line;
  p.a = centre + Eigen::Vector3d(r0 * std::cos(a0), r0 * std::sin(a0), 0.0);
  p.b = centre + Eigen::Vector3d(r1 * std::cos(a0 + sweep), r1 * std::sin(a0 + sweep), dw);
  return p;
}

Eigen::Vector3d on(const Piece& p, double f) {
  if (!p.arc) return p.a + f * (p.b - p.a);
  const double angle = p.a0 + f * p.sweep, r = p.r0 + f * (p.r1 - p.r0);
  return p.centre + Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), f * p.dw);
}

/// What the executed path does: points, and rapids between them (nullopt).
using Steps = std::vector<std::optional<Eigen::Vector3d>>;

/// A move from a to b as verify samples a short one: 17 points, both ends included.
void cut(Steps& steps, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  for (int k = 0; k <= 16; ++k) steps.emplace_back(a + (b - a) * (k / 16.0));
}

/// Every distance, and what is left uncut, the same bit for bit from both searches.
void expect_as_full_search(const std::vector<Piece>& pieces, const Steps& steps) {
  ListPath kept_path(pieces), full_path(pieces);
  PathSearch<ListPath> kept(kept_path, Candidates::kept), full(full_path, Candidates::none);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (!steps[k]) {
      kept.rapid(), full.rapid();
      continue;
    }
    const std::optional<double> a = kept.distance(*steps[k]), b = full.distance(*steps[k]);
    ASSERT_EQ(a.has_value(), b.has_value()) << "step " << k;
    if (a) {
      ASSERT_EQ(*a, *b) << "step " << k;
    }
  }
  const auto [kept_length, kept_line] = kept.uncut();
  const auto [full_length, full_line] = full.uncut();
  EXPECT_EQ(kept_length, full_length);
  EXPECT_EQ(kept_line, full_line);
}

TEST(PathSearch, KeptCandidatesFindWhatTheFullSearchFindsWhereASteepHelixCrossesALine) {
  // The helix rises 2 mm over half a turn of 0.2 mm radius and crosses the line at (0, 0.2, 1):
  // its distance at the point's angle changes three times faster than the point moves. The
  // executed path comes along the line to the crossing and steps onto the helix there.
  const std::vector<Piece> pieces{segment({0.3, 0.2, 1}, {-0.3, 0.2, 1}, 3),
                                  arc({0, 0, 0}, 0.2, 0.2, 0.0, std::numbers::pi, 2.0, 5)};
  const Eigen::Vector3d on_helix = on(pieces[1], 0.5 + 0.005 / std::numbers::pi);
  Steps steps;
  cut(steps, {0.3, 0.2, 1}, {0, 0.2, 1});
  cut(steps, {0, 0.2, 1}, on_helix);
  steps.emplace_back();
  cut(steps, {0.3, 0.2, 1}, {-0.3, 0.2, 1});
  steps.emplace_back();
  for (int k = 0; k < 64; ++k) cut(steps, on(pieces[1], k / 64.0), on(pieces[1], (k + 1) / 64.0));
  expect_as_full_search(pieces, steps);
}

TEST(PathSearch, KeptCandidatesFindWhatTheFullSearchFindsOnASpiral) {
  // A flat spiral whose radius grows from 0.1 to 0.38 mm in 0.49 rad: its distance at the
  // point's angle changes many times faster than the point moves. A line passes its start;
  // the executed path comes along the line and steps onto the spiral there, then runs along
  // the spiral.
  const Piece spiral = arc({0, 0, 0}, 0.0977, 0.3821, 0.0, 0.4875, 0.0, 5);
  const std::vector<Piece> pieces{segment({0.5, 0.0008, 0}, {-0.5, 0.0008, 0}, 3), spiral};
  const Eigen::Vector3d onto = on(spiral, 0.1985);
  Steps steps;
  cut(steps, {0.5, 0.0008, 0}, {onto.x(), 0.0008, 0});
  cut(steps, {onto.x(), 0.0008, 0}, onto);
  steps.emplace_back();
  for (int k = 0; k < 64; ++k) cut(steps, on(spiral, k / 64.0), on(spiral, (k + 1) / 64.0));
  expect_as_full_search(pieces, steps);
}

TEST(PathSearch, KeptCandidatesFindWhatTheFullSearchFindsWhereThePathIsTracedBack) {
  // The original: 2,000 pieces of 0.5 um along X. The executed path goes out along it in
  // moves of 10 um and comes back over it 0.1 um aside: the window moves back behind where
  // the candidates were gathered.
  std::vector<Piece> pieces;
  for (int k = 0; k < 2000; ++k) pieces.push_back(segment({0.0005 * k, 0, 0}, {0.0005 * (k + 1), 0, 0}, 3 + k));
  Steps steps;
  for (int k = 0; k < 100; ++k) cut(steps, {0.01 * k, 0, 0}, {0.01 * (k + 1), 0, 0});
  for (int k = 100; k > 10; --k) cut(steps, {0.01 * k, 1e-4, 0}, {0.01 * (k - 1), 1e-4, 0});
  expect_as_full_search(pieces, steps);
}

TEST(PathSearch, KeptCandidatesFindWhatTheFullSearchFindsOnASpringPassAsLongAsTheWindow) {
  // A circle of 10 mm radius in about 4,096 chords (the window ahead), cut twice, the second
  // time 0.2 um further in; the executed path runs 0.3 um in, nearer the second pass all
  // through the first. The second pass's pieces come into the window ahead one by one while
  // the point is still on the first pass, right beside them.
  for (const int chords : {4094, 4095, 4096}) {
    std::vector<Piece> pieces;
    Steps steps;
    auto at = [&](int k, double radius) {
      const double angle = 2 * std::numbers::pi * k / chords;
      return Eigen::Vector3d(radius * std::cos(angle), radius * std::sin(angle), 0);
    };
    for (int pass = 0; pass < 2; ++pass)
      for (int k = 0; k < chords; ++k) {
        const double radius = pass == 0 ? 10.0 : 10.0 - 2e-4;
        pieces.push_back(segment(at(k, radius), at(k + 1, radius), static_cast<std::uint32_t>(3 + pass * chords + k)));
        cut(steps, at(k, 10.0 - 3e-4), at(k + 1, 10.0 - 3e-4));
      }
    expect_as_full_search(pieces, steps);
  }
}

TEST(PathSearch, APointIsMeasuredAgainstThePassItCutsNotALaterOneOverTheSamePlace) {
  // A 10 mm square in 5 chords a side, traced twice, the second time 0.2 um further in;
  // along the first pass's first side the executed point runs 0.15 um in: it is 0.15 um
  // off the cut it makes, though 0.05 um from the later pass over the same place.
  const auto corner = [](int k, double in) {
    const std::array<Eigen::Vector3d, 4> c{Eigen::Vector3d(in, in, 0), Eigen::Vector3d(10 - in, in, 0),
                                           Eigen::Vector3d(10 - in, 10 - in, 0), Eigen::Vector3d(in, 10 - in, 0)};
    return c[static_cast<std::size_t>(k % 4)];
  };
  std::vector<Piece> pieces;
  for (const double in : {0.0, 2e-4})
    for (int side = 0; side < 4; ++side)
      for (int k = 0; k < 5; ++k) {
        const Eigen::Vector3d a = corner(side, in), b = corner(side + 1, in);
        pieces.push_back(segment(a + (b - a) * (k / 5.0), a + (b - a) * ((k + 1) / 5.0),
                                 static_cast<std::uint32_t>(pieces.size() + 3)));
      }
  ListPath path(pieces);
  PathSearch<ListPath> search(path);
  for (int k = 1; k < 50; ++k) {
    const std::optional<double> d = search.distance({0.2 * k, 1.5e-4, 0});
    ASSERT_TRUE(d.has_value());
    EXPECT_NEAR(*d, 1.5e-4, 1e-12) << "point " << k;
  }
}

TEST(PathSearch, ManyTurnsOfTheSameCircleAreEachFoundCutAndOneLeftOutIsNamed) {
  // 2,000 full circles over one another, each one piece: every executed point is near every
  // one of them. All cut: nothing uncut; the last one left out: its length, at its line.
  std::vector<Piece> pieces;
  for (std::uint32_t k = 0; k < 2000; ++k) pieces.push_back(arc({0, 0, 0}, 10.0, 10.0, 0.0, 2 * std::numbers::pi, 0.0, 5 + k));
  for (const std::size_t cut_turns : {std::size_t{2000}, std::size_t{1999}}) {
    ListPath path(pieces);
    PathSearch<ListPath> search(path);
    for (std::size_t turn = 0; turn < cut_turns; ++turn)
      for (int k = turn == 0 ? 0 : 1; k <= 32; ++k) {
        const double angle = 2 * std::numbers::pi * k / 32;
        const std::optional<double> d = search.distance(10.0 * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0));
        ASSERT_TRUE(d.has_value());
        ASSERT_LT(*d, 1e-9) << "turn " << turn << ", point " << k;
      }
    const auto [length, line] = search.uncut();
    if (cut_turns == 2000) {
      EXPECT_EQ(length, 0.0);
    } else {
      EXPECT_NEAR(length, 2 * std::numbers::pi * 10.0, 1e-6);
      EXPECT_EQ(line, 5u + 1999u);
    }
  }
}

TEST(PathSearch, APassLeftOutOfARasterCloserThanTheCandidateRadiusIsNamed) {
  // A one-way raster: six passes of 10 mm, 20 um apart, each of ten pieces, a rapid back
  // between them. The output leaves out the fourth: the point after the rapid lands on the
  // fifth, 20 um from the fourth it is said to skip; that pass is named, by its first line.
  std::vector<Piece> pieces;
  for (int pass = 0; pass < 6; ++pass)
    for (int k = 0; k < 10; ++k)
      pieces.push_back(segment({k * 1.0, 0.02 * pass, 0}, {(k + 1) * 1.0, 0.02 * pass, 0},
                               static_cast<std::uint32_t>(10 + 10 * pass + k)));
  ListPath path(pieces);
  PathSearch<ListPath> search(path);
  for (const int pass : {0, 1, 2, 4, 5}) {
    search.rapid();
    for (int k = 0; k <= 40; ++k) {
      const std::optional<double> d = search.distance({0.25 * k, 0.02 * pass, 0});
      ASSERT_TRUE(d.has_value());
      EXPECT_LT(*d, 1e-12) << "pass " << pass << ", point " << k;
    }
  }
  const auto [length, line] = search.uncut();
  EXPECT_NEAR(length, 10.0, 1e-9);
  EXPECT_EQ(line, 40u);
}

TEST(PathSearch, ASegmentShownFartherByItsBallIsFarther) {
  // What skipping a piece on its ball rests on: where farther_than(p, d) says so, the
  // segment's distance from p is more than d, for segments of a micrometre to 100 mm far
  // out in the workspace (millimetres round to 1e-13 there), and points on their line.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int shown = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Vector3d a = 900.0 * Eigen::Vector3d(unit(random), unit(random), unit(random));
    const double length = std::pow(10.0, -3 + 5 * (0.5 + 0.5 * unit(random)));
    const Eigen::Vector3d b = a + length * Eigen::Vector3d(unit(random), unit(random), unit(random)).normalized();
    Piece piece = segment(a, b, 1);
    piece.prepare_bounds();
    const Eigen::Vector3d p =
        trial % 2 == 0 ? Eigen::Vector3d(a + (1.0 + 1e-9 * (0.5 + 0.5 * unit(random))) * (b - a))
                       : Eigen::Vector3d(a + 2.0 * length * Eigen::Vector3d(unit(random), unit(random), unit(random)));
    const double distance = piece.distance(p);
    for (const double d : {0.0, 0.5 * distance, distance * (1 - 1e-12), distance, 2.0 * distance}) {
      if (!piece.farther_than(p, d)) continue;
      ++shown;
      ASSERT_GT(distance, d) << "trial " << trial;
    }
  }
  EXPECT_GT(shown, 5000) << "the ball shows most pieces farther than half their distance";
}

TEST(PathSearch, AnArcsLowerDistanceIsNeverMoreThanTheDistanceToAnyOfItsPoints) {
  // What keeping an arc as a candidate rests on: for arcs, helices and spirals of any size,
  // turning either way in a turned (or mirrored) frame, the bound is no more than the
  // distance to the nearest of 2,001 points along the arc, wherever the point is.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 1200; ++trial) {
    Piece p = arc({0, 0, 0}, 0.01 + 5 * unit(random), 0.01 + 5 * unit(random), 7 * unit(random),
                  1e-3 + (trial % 3 == 0 ? 6 * std::numbers::pi : std::numbers::pi) * unit(random),
                  trial % 2 == 0 ? 0.0 : -3 + 6 * unit(random), 1);
    p.ccw = trial % 4 < 2;
    const Eigen::Matrix3d turn =
        Eigen::Quaterniond(unit(random), unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5)
            .normalized()
            .toRotationMatrix();
    p.centre = Eigen::Vector3d(unit(random), unit(random), unit(random));
    p.e1 = turn.col(0), p.e2 = turn.col(1), p.n = (trial % 5 == 0 ? -1.0 : 1.0) * turn.col(2);
    p.prepare_bounds();
    const double reach = std::max(p.r0, p.r1) + std::abs(p.dw);
    for (int k = 0; k < 20; ++k) {
      const Eigen::Vector3d q =
          p.centre + reach * Eigen::Vector3d(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5) * 2.4;
      double nearest = std::numeric_limits<double>::infinity();
      for (int j = 0; j <= 2000; ++j) {
        const double f = j / 2000.0, angle = p.a0 + (p.ccw ? 1 : -1) * f * p.sweep, r = p.r0 + f * (p.r1 - p.r0);
        const Eigen::Vector3d on_arc =
            p.centre + r * (std::cos(angle) * p.e1 + std::sin(angle) * p.e2) + f * p.dw * p.n;
        nearest = std::min(nearest, (q - on_arc).norm());
      }
      ASSERT_LE(p.arc_lower_distance(q), nearest + 1e-9) << "trial " << trial << " point " << k;
    }
  }
}

}  // namespace
}  // namespace ccomp::compensate
