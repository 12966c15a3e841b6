// ccomp export --control isg, checked as Beckhoff TwinCAT CNC's Volumetric Compensation
// would use it: the configuration list and the ISG_CSV file are read by a loader written
// here from ISG's documentation (a header naming the columns, // comments, # a new block;
// GRID interpolation: linear on a complete grid), the error it gives subtracted from the
// commanded X, Y and Z, and the model's tool tip measured over the workspace.
#include "ccomp/controller/volume_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "ccomp/error.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// The list's keys and values, one pair a line.
std::map<std::string, std::string> read_list(const std::string& text) {
  std::map<std::string, std::string> keys;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key, value;
    if (words >> key >> value) keys[key] = value;
  }
  return keys;
}

/// An ISG_CSV grid of X, Y, Z with EXX, EYY, EZZ: the error at commanded X Y Z, trilinear
/// in the cell holding it (the value at each of its 8 corners weighted by the products of
/// the point's fractions x or 1 - x along each axis), held at the ends beyond the grid.
class IsgGrid {
 public:
  explicit IsgGrid(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    std::vector<std::string> header;
    std::map<std::array<double, 3>, Eigen::Vector3d> rows;
    while (std::getline(in, line)) {
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string::npos || line.compare(first, 2, "//") == 0) continue;
      EXPECT_NE(line[first], '#') << "one block only";
      std::istringstream words(line);
      if (header.empty()) {
        for (std::string w; words >> w;) header.push_back(w);
        continue;
      }
      std::map<std::string, double> row;
      for (const std::string& name : header) {
        double v = std::nan("");
        EXPECT_TRUE(words >> v) << "a short row: " << line;
        row[name] = v;
      }
      std::string rest;
      EXPECT_FALSE(words >> rest) << "a long row: " << line;
      const std::array<double, 3> at{row.at("X"), row.at("Y"), row.at("Z")};
      EXPECT_FALSE(rows.contains(at)) << "a node twice";
      rows[at] = Eigen::Vector3d(row.at("EXX"), row.at("EYY"), row.at("EZZ"));
      for (std::size_t a = 0; a < 3; ++a) axes_[a].insert(at[a]);
    }
    for (std::size_t a = 0; a < 3; ++a) positions_[a].assign(axes_[a].begin(), axes_[a].end());
    EXPECT_EQ(rows.size(), positions_[0].size() * positions_[1].size() * positions_[2].size()) << "not a full grid";
    for (const auto& [at, e] : rows) values_[at] = e;
  }

  [[nodiscard]] std::size_t nodes() const { return values_.size(); }
  [[nodiscard]] const std::vector<double>& positions(std::size_t axis) const { return positions_[axis]; }

  [[nodiscard]] Eigen::Vector3d error_at(const Eigen::Vector3d& p) const {
    std::array<std::size_t, 3> lower{};
    std::array<double, 3> fraction{};
    for (std::size_t a = 0; a < 3; ++a) {
      const std::vector<double>& v = positions_[a];
      const double x = std::clamp(p[static_cast<Eigen::Index>(a)], v.front(), v.back());
      std::size_t k = 0;
      while (k + 2 < v.size() && x >= v[k + 1]) ++k;
      lower[a] = k;
      fraction[a] = (x - v[k]) / (v[k + 1] - v[k]);
    }
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int dx = 0; dx < 2; ++dx)
      for (int dy = 0; dy < 2; ++dy)
        for (int dz = 0; dz < 2; ++dz) {
          const double w = (dx ? fraction[0] : 1 - fraction[0]) * (dy ? fraction[1] : 1 - fraction[1]) *
                           (dz ? fraction[2] : 1 - fraction[2]);
          const std::array<double, 3> node{positions_[0][lower[0] + dx], positions_[1][lower[1] + dy],
                                           positions_[2][lower[2] + dz]};
          sum += w * values_.at(node);
        }
    return sum;
  }

 private:
  std::array<std::set<double>, 3> axes_;
  std::array<std::vector<double>, 3> positions_;
  std::map<std::array<double, 3>, Eigen::Vector3d> values_;
};

/// The model's tool tip (machine-axis directions, um) with X Y Z commanded to `commanded`
/// against the perfect machine at `q`, all three travelling `direction`.
Eigen::Vector3d tip_miss_um(const model::ForwardModel& f, model::ForwardData& d, const model::ChainQ& q,
                            const model::ChainQ& commanded, int direction) {
  model::Conditions conditions;
  conditions.temperatures.assign(f.machine().sensors.size(), 20.0);
  model::forward(f, d, q, conditions, false, model::Evaluate::nominal);
  const Eigen::Vector3d wanted = d.nominal;
  conditions.directions[0] = conditions.directions[1] = conditions.directions[2] = direction;
  model::forward(f, d, commanded, conditions);
  return 1e3 * (d.nominal_chain.oMp.R * (d.actual - wanted));
}

double json_number(const std::string& json, const std::string& object, const std::string& key) {
  std::smatch m;
  const std::regex r("\"" + object + "\": \\{[^}]*\"" + key + "\": (-?[0-9.e+-]+)");
  EXPECT_TRUE(std::regex_search(json, m, r)) << object << "." << key << " in " << json;
  return std::stod(m[1]);
}

const std::string kReadings = " --sensor bed=20 --sensor column=20 --sensor spindle=20";

struct Exported {
  CommandResult result;
  std::string list, csv;
};

Exported export_isg(const std::string& model, const std::string& options) {
  const std::string dir = temp_dir("isg_volume");
  const std::string csv = dir + "/" + model + ".csv";
  Exported e;
  e.result = run_command(shell_quote(ccomp_binary()) + " export -m " +
                         shell_quote(source_dir() + "/samples/machines/" + model + ".yaml") + " --control isg -o " +
                         shell_quote(csv) + " --json" + options);
  if (e.result.exit_code == 0) e.list = read_file(dir + "/" + model + ".lis"), e.csv = read_file(csv);
  return e;
}

struct Measured {
  double max_before = 0, max_after = 0, max_after_at_nodes = 0;
};

/// The grid applied as the control applies it, at `count` random points of its box and at
/// its nodes, both directions of travel, with B at `b` (rad) and a 100 mm tool; errors
/// relative to the reference point's (where the work offset takes them).
Measured measure(const std::string& model, const IsgGrid& grid, double b, std::size_t count) {
  const model::MachineModel machine = sample_machine(model);
  const model::ForwardModel f(machine);
  model::ForwardData d(f);
  model::ChainQ reference = model::ChainQ::Zero();
  reference[4] = b, reference[9] = 100;
  const Eigen::Vector3d offset = tip_miss_um(f, d, reference, reference, +1);
  auto corrected = [&](const model::ChainQ& q) {
    model::ChainQ c = q;
    c.head<3>() -= grid.error_at(q.head<3>());
    return c;
  };
  Measured m;
  std::mt19937 random(7);
  auto at = [&](std::size_t a) {
    return std::uniform_real_distribution<double>(grid.positions(a).front(), grid.positions(a).back())(random);
  };
  for (std::size_t n = 0; n < count; ++n) {
    model::ChainQ q = reference;
    q.head<3>() << at(0), at(1), at(2);
    for (int direction : {+1, -1}) {
      m.max_before = std::max(m.max_before, (tip_miss_um(f, d, q, q, direction) - offset).norm());
      m.max_after = std::max(m.max_after, (tip_miss_um(f, d, q, corrected(q), direction) - offset).norm());
    }
  }
  for (const double x : grid.positions(0))
    for (const double y : {grid.positions(1).front(), 0.0, grid.positions(1).back()})
      for (const double z : grid.positions(2)) {
        model::ChainQ q = reference;
        q.head<3>() << x, y, z;
        const double mean_error = 0.5 * ((tip_miss_um(f, d, q, corrected(q), +1) - offset) +
                                         (tip_miss_um(f, d, q, corrected(q), -1) - offset))
                                            .norm();
        m.max_after_at_nodes = std::max(m.max_after_at_nodes, mean_error);
      }
  return m;
}

TEST(IsgVolume, TheListNamesTheGridAndTheGridIsComplete) {
  const Exported e = export_isg("hmc-xyzb-geometric", " --step 50");
  ASSERT_EQ(e.result.exit_code, 0) << e.result.err;
  const auto keys = read_list(e.list);
  EXPECT_EQ(keys.at("workpiece_axes"), "0");
  EXPECT_EQ(keys.at("X"), "1");
  EXPECT_EQ(keys.at("Y"), "2");
  EXPECT_EQ(keys.at("Z"), "3");
  EXPECT_EQ(keys.at("interpolation"), "GRID");
  EXPECT_EQ(keys.at("file[0]"), "hmc-xyzb-geometric.csv");
  EXPECT_EQ(keys.at("file_format[0]"), "ISG_CSV");
  const IsgGrid grid(e.csv);
  // X -500..500, Y -450..450, Z -500..500 every 50 mm.
  EXPECT_EQ(grid.positions(0).size(), 21U);
  EXPECT_EQ(grid.positions(1).size(), 19U);
  EXPECT_EQ(grid.positions(2).size(), 21U);
  EXPECT_EQ(grid.nodes(), 21U * 19U * 21U);
  EXPECT_EQ(json_number(e.result.out, "workspace", "points"), 4000);
  EXPECT_LT(grid.error_at(Eigen::Vector3d::Zero()).norm(), 1e-9) << "0 at the reference node";
}

// A smooth model (error motions of low order, squareness): between nodes 50 mm apart the
// grid leaves h^2/8 |e''|, a few nanometres; at the nodes the digits (1 nm).
TEST(IsgVolume, ASmoothModelIsReproducedOverTheWorkspace) {
  for (const double b_deg : {0.0, 90.0}) {
    const Exported e = export_isg("hmc-xyzb-geometric", " --step 50" + std::string(b_deg != 0 ? " --at B=90" : ""));
    ASSERT_EQ(e.result.exit_code, 0) << e.result.err;
    const Measured m = measure("hmc-xyzb-geometric", IsgGrid(e.csv), b_deg * M_PI / 180.0, 400);
    EXPECT_GT(m.max_before, 20.0) << "B " << b_deg;
    EXPECT_LT(m.max_after, 0.05) << "B " << b_deg << ", before " << m.max_before;
    EXPECT_LT(m.max_after_at_nodes, 0.005) << "B " << b_deg;
    EXPECT_NEAR(json_number(e.result.out, "workspace", "max_after_um"), m.max_after, 0.02);
  }
}

// The full model: its lead screws' 10-12 mm periods are far shorter than the grid's step,
// so the grid leaves them out (the axis' pitch table carries them) rather than alias them;
// its backlash it holds as the mean of both directions. What is left is their size against
// the reference point's (the work offset, probed travelling up): at most twice each screw's
// amplitude (2.0, 1.4, 1.6 um) plus the whole reversal (4, 3, 5 um) on each axis, and at
// least the reversals, which no table of one value a node can take. The export says so.
// A straightness that switches with X's approach is held as the mean of both, as a
// reversal is, and named with them.
TEST(IsgVolume, AnyTermOfAnApproachIsNamedWithTheReversals) {
  const std::string dir = temp_dir("isg_volume_approach");
  write_file(dir + "/m.yaml", read_file(source_dir() + "/samples/machines/hmc-xyzb.yaml") +
                                  "  - {name: EZX, variable: vx, form: polynomial, unit: um, coefficients: [0, 2]}\n");
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " export -m " + shell_quote(dir + "/m.yaml") +
                                      " --control isg -o " + shell_quote(dir + "/m.csv") + " --json" + kReadings);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"reversal_terms\": [\"EXX\", \"EYY\", \"EZZ\", \"EBB\", \"EZX\"]"), std::string::npos)
      << r.out;
}

TEST(IsgVolume, WhatTheGridCannotHoldIsNamedAndMeasured) {
  const Exported e = export_isg("hmc-xyzb", kReadings);
  ASSERT_EQ(e.result.exit_code, 0) << e.result.err;
  const Measured m = measure("hmc-xyzb", IsgGrid(e.csv), 0.0, 400);
  const double bound = std::hypot(2 * 2.01 + 4, 2 * 1.39 + 3, 2 * 1.62 + 5);
  EXPECT_GT(m.max_before, 30.0);
  EXPECT_LT(m.max_after, bound) << "before " << m.max_before;
  EXPECT_GT(m.max_after, std::hypot(4.0, 3.0, 5.0) - 0.2);
  EXPECT_NEAR(json_number(e.result.out, "workspace", "max_after_um"), m.max_after, 0.1 * m.max_after);
  EXPECT_NE(e.result.out.find("\"left_out_terms\": [\"EXX\", \"EYY\", \"EZZ\"]"), std::string::npos) << e.result.out;
  EXPECT_NE(e.result.out.find("\"reversal_terms\": [\"EXX\", \"EYY\", \"EZZ\", \"EBB\"]"), std::string::npos);
  // A step fine enough for the screws would take 58 million nodes: refused, with the reason.
  const Exported fine = export_isg("hmc-xyzb", kReadings + " --step 2.5");
  EXPECT_EQ(fine.result.exit_code, 2) << "more than a million nodes is refused";
  EXPECT_NE(fine.result.err.find("--step"), std::string::npos) << fine.result.err;
}

TEST(IsgVolume, OptionsThatDoNotApplyAreRefusedAndWriteNothing) {
  const std::string dir = temp_dir("isg_refused");
  for (const std::string options : {" --axis X", " -o -", " --at X=10", " --from 0", " -o {d}/v.lis", " -o {d}/v.LIS",
                                    " -o '{d}/a b.csv'", " --step 0.5"}) {
    std::string expanded = options;
    if (const auto at = expanded.find("{d}"); at != std::string::npos) expanded.replace(at, 3, dir);
    const CommandResult r =
        run_command(shell_quote(ccomp_binary()) + " export -m " +
                    shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") + " --control isg" +
                    (options.find("-o") == std::string::npos ? " -o " + dir + "/v.csv" : "") + expanded);
    EXPECT_EQ(r.exit_code, 2) << options << ": " << r.err;
    EXPECT_FALSE(r.err.empty()) << options;
    EXPECT_TRUE(std::filesystem::is_empty(dir)) << options << " wrote something";
  }
}

// The list is the user's once edited (axis numbers, the CSV's path on the control): a
// second export keeps it, and says so.
TEST(IsgVolume, AListEditedForTheMachineIsKept) {
  const std::string dir = temp_dir("isg_kept");
  const std::string run = shell_quote(ccomp_binary()) + " export -m " +
                          shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") +
                          " --control isg --step 100 -o " + shell_quote(dir + "/v.csv");
  const CommandResult first = run_command(run);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(first.err.find("\n  kept "), std::string::npos) << first.err;
  const std::string edited = read_file(dir + "/v.lis") + "x 5\n";
  write_file(dir + "/v.lis", edited);
  const CommandResult again = run_command(run);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(read_file(dir + "/v.lis"), edited);
  EXPECT_NE(again.err.find("\n  kept "), std::string::npos) << again.err;
}

// The sign the docs state: at a node along X, EXX is the tool tip's error along X (actual
// less nominal, against the reference's), as a laser along X reads it, to first order.
TEST(IsgVolume, EachValueIsTheTipsErrorAlongItsAxis) {
  const Exported e = export_isg("hmc-xyzb-geometric", " --step 50");
  ASSERT_EQ(e.result.exit_code, 0) << e.result.err;
  const IsgGrid grid(e.csv);
  const model::MachineModel machine = sample_machine("hmc-xyzb-geometric");
  const model::ForwardModel f(machine);
  model::ForwardData d(f);
  model::ChainQ reference = model::ChainQ::Zero();
  reference[9] = 100;
  const Eigen::Vector3d offset = tip_miss_um(f, d, reference, reference, 0);
  for (const double x : {-500.0, -250.0, 250.0, 500.0}) {
    model::ChainQ q = reference;
    q[0] = x;
    const double laser_um = (tip_miss_um(f, d, q, q, 0) - offset)[0];
    const double written_um = grid.error_at(Eigen::Vector3d(x, 0, 0))[0] * 1e3;
    EXPECT_GT(std::abs(laser_um), 1.0) << x;
    EXPECT_NEAR(written_um, laser_um, 0.01 * std::abs(laser_um) + 0.002) << x;
  }
}

// The library alone, on small models made here.
model::MachineModel xyz_model(const std::string& terms) {
  return model::parse_machine_model(
      "name: small\ndialect: linuxcnc\naxes:\n  X: {type: linear, min: -100, max: 100}\n"
      "  Y: {type: linear, min: -100, max: 100}\n  Z: {type: linear, min: -100, max: 100}\nchain:\n"
      "  workpiece:\n    - {link: X, axis: X, direction: [-1, 0, 0]}\n  tool:\n"
      "    - {link: Y, axis: Y, direction: [0, 1, 0]}\n    - {link: Z, axis: Z, direction: [0, 0, 1]}\n"
      "terms:\n" +
          terms,
      "small.yaml");
}

controller::VolumeOptions options_every(double step) {
  controller::VolumeOptions o;
  for (auto& g : o.grids) g = controller::Grid{-100, 100, step};
  return o;
}

TEST(VolumeTable, LeftOutHarmonicsAreSampledAsZeroAndTheRestKept) {
  const model::MachineModel m = xyz_model(
      "  - {name: EXX, form: periodic, period: 10 mm, unit: um, harmonics: [[2, 1]]}\n"
      "  - {name: EYY, form: periodic, period: 400 mm, unit: um, harmonics: [[3, 0], [0, 0], [0, 0], [0, 0], [0, 0], "
      "[0, 0], [0, 0], [0, 0], [0, 0], [1, 0]]}\n");
  const model::ForwardModel f(m);
  controller::VolumeOptions o = options_every(25);
  o.left_out = {{0, 1}, {1, 5}};  // all of EXX; EYY's harmonics from the 5th (80 mm) on
  const controller::VolumeTable table = controller::sample_volume_table(f, o);
  double most_x = 0, most_y = 0;
  for (const Eigen::Vector3d& c : table.correction) {
    most_x = std::max(most_x, std::abs(c[0]));
    most_y = std::max(most_y, std::abs(c[1]));
  }
  EXPECT_LT(most_x, 1e-9) << "EXX left out whole";
  EXPECT_GT(most_y, 2e-3) << "EYY's first harmonic kept";
  // At Y = 50 the correction is the first harmonic's alone, against its value at 0.
  const double y50 = table.correction_at(Eigen::Vector3d(0, 50, 0))[1];
  EXPECT_NEAR(y50, -(3e-3 * std::cos(2 * M_PI * 50 / 400) - 3e-3), 1e-7);
}

TEST(VolumeTable, OnlyPeriodicTermsCanBeLeftOut) {
  const model::MachineModel m = xyz_model("  - {name: EXX, form: polynomial, unit: um, coefficients: [0, 0.01]}\n");
  const model::ForwardModel f(m);
  controller::VolumeOptions o = options_every(50);
  o.left_out = {{0, 1}};
  EXPECT_THROW((void)controller::sample_volume_table(f, o), Error);
}

TEST(VolumeTable, InterpolatesInsideHoldsBeyondAndTakesOneNodeAxes) {
  controller::VolumeTable t;
  t.positions = {std::vector<double>{0, 10}, std::vector<double>{0, 10}, std::vector<double>{5}};
  // c = (x, 2 y, 0) at the nodes (X fastest): trilinear reproduces it inside, holds it
  // beyond the ends.
  for (std::size_t j = 0; j < 2; ++j)
    for (std::size_t i = 0; i < 2; ++i)
      t.correction.emplace_back(10.0 * static_cast<double>(i), 20.0 * static_cast<double>(j), 0);
  EXPECT_TRUE(t.correction_at(Eigen::Vector3d(2.5, 7.5, 5)).isApprox(Eigen::Vector3d(2.5, 15, 0)));
  EXPECT_TRUE(t.correction_at(Eigen::Vector3d(10, 10, 5)).isApprox(Eigen::Vector3d(10, 20, 0)));
  EXPECT_TRUE(t.correction_at(Eigen::Vector3d(25, -3, 99)).isApprox(Eigen::Vector3d(10, 0, 0)));
  EXPECT_TRUE(t.correction_at(Eigen::Vector3d(std::nan(""), 5, 5)).allFinite());
}

}  // namespace
}  // namespace ccomp::test
