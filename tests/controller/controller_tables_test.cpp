// ccomp export, checked as each control would use its file: the table is read back by a
// loader written here from the control's documentation (not ccomp's writer), applied to
// the commanded positions as the control applies it, and the model's tool tip measured
// along the table's line. The error left must be what the export says, and far below
// the error without the table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <regex>
#include <sstream>

#include "ccomp/kinematics/pose.hpp"
#include "ccomp/model/forward.hpp"
#include "job_runner.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// What a loaded table adds to the axes' commands (X Y Z A B C U V W, in the table's
/// units: mm, deg) at commanded positions p (the same units), travelling up (+1) or down (-1).
using Axes = Eigen::Matrix<double, 9, 1>;
using Corrections = std::function<Axes(const Axes& p, int direction)>;

/// Linear interpolation over equidistant points from `min` every `step`, constant beyond.
double equidistant(const std::vector<double>& v, double min, double step, double p) {
  const double x = (p - min) / step;
  if (x <= 0) return v.front();
  if (x >= static_cast<double>(v.size() - 1)) return v.back();
  const auto k = static_cast<std::size_t>(x);
  return v[k] + (x - static_cast<double>(k)) * (v[k + 1] - v[k]);
}

// LinuxCNC: usrmotLoadComp() reads "%lf %lf %lf" lines until one is not a triplet; type
// 0 stores trims nominal - value, type 1 the values; compute_screw_comp() adds the
// trim of the entry below the commanded position plus its slope times the distance,
// forward trims while the joint moves up, reverse while it moves down; beyond the
// first and last entries the trims stay constant.
Corrections load_linuxcnc(const std::string& text, int type, std::size_t axis) {
  struct Entry {
    double nominal, fwd, rev;
  };
  std::vector<Entry> entries;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    double n, f, r;
    if (std::sscanf(line.c_str(), "%lf %lf %lf", &n, &f, &r) != 3) break;
    entries.push_back(type == 0 ? Entry{n, n - f, n - r} : Entry{n, f, r});
  }
  EXPECT_GT(entries.size(), 10U);
  return [entries, axis](const Axes& at, int direction) {
    const double p = at[static_cast<Eigen::Index>(axis)];
    double trim = 0;
    auto pick = [direction](const Entry& e) { return direction > 0 ? e.fwd : e.rev; };
    if (p < entries.front().nominal) {
      trim = pick(entries.front());
    } else if (p >= entries.back().nominal) {
      trim = pick(entries.back());
    } else {
      std::size_t k = 0;
      while (p >= entries[k + 1].nominal) ++k;
      const double slope = (pick(entries[k + 1]) - pick(entries[k])) / (entries[k + 1].nominal - entries[k].nominal);
      trim = pick(entries[k]) + slope * (p - entries[k].nominal);
    }
    Axes c = Axes::Zero();
    c[static_cast<Eigen::Index>(axis)] = trim;
    return c;
  };
}

// Fanuc: parameters N0xxxxAaPv; data N1nnnnPv, point n's value the change of the
// correction from point n-1 to n (detection units x magnification 3623), 0 at the
// reference point 3620, points every 3624 units; the backlash 1851 taken off travelling
// down (the reference approached travelling up).
Corrections load_fanuc(const std::string& text, std::size_t axis, double unit) {
  std::map<int, long> parameters, data;
  const std::regex parameter("N0(\\d{4})A\\d+P(-?\\d+)"), point("N1(\\d{4})P(-?\\d+)");
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_match(line, m, parameter)) parameters[std::stoi(m[1])] = std::stol(m[2]);
    if (std::regex_match(line, m, point)) data[std::stoi(m[1])] = std::stol(m[2]);
  }
  const int reference = static_cast<int>(parameters.at(3620)), first = static_cast<int>(parameters.at(3621)),
            last = static_cast<int>(parameters.at(3622));
  const double magnification = static_cast<double>(parameters.at(3623));
  const double interval = static_cast<double>(parameters.at(3624)) * unit;
  const double backlash = static_cast<double>(parameters.at(1851)) * unit;
  std::vector<double> absolute(static_cast<std::size_t>(last - first + 1), 0.0);
  for (int n = reference + 1; n <= last; ++n)
    absolute[static_cast<std::size_t>(n - first)] =
        absolute[static_cast<std::size_t>(n - 1 - first)] + static_cast<double>(data.at(n)) * magnification * unit;
  for (int n = reference - 1; n >= first; --n)
    absolute[static_cast<std::size_t>(n - first)] =
        absolute[static_cast<std::size_t>(n + 1 - first)] - static_cast<double>(data.at(n + 1)) * magnification * unit;
  const double min = (first - reference) * interval;
  return [absolute, min, interval, backlash, axis](const Axes& p, int direction) {
    Axes c = Axes::Zero();
    c[static_cast<Eigen::Index>(axis)] =
        equidistant(absolute, min, interval, p[static_cast<Eigen::Index>(axis)]) - (direction < 0 ? backlash : 0.0);
    return c;
  };
}

// Siemens 840D sl: $AA_ENC_COMP[0,N,AXn] the measuring system's error (a positive value
// moves the axis the negative way) from $AA_ENC_COMP_MIN every $AA_ENC_COMP_STEP;
// $AN_CEC[t,N] the correction added to $AN_CEC_OUTPUT_AXIS[t] as $AN_CEC_INPUT_AXIS[t]
// moves, in the direction $AN_CEC_DIRECTION[t] (0 both).
Corrections load_siemens(const std::string& text) {
  std::map<int, std::map<std::string, std::string>> cec;  // per table: parameter -> value
  std::map<int, std::vector<double>> cec_values;
  std::vector<double> lec;
  double lec_step = 0, lec_min = 0;
  int lec_axis = 0;
  const std::regex lec_value(R"(\$AA_ENC_COMP\[0,(\d+),AX(\d+)\]=(\S+))"),
      lec_parameter(R"(\$AA_ENC_COMP_(\w+)\[0,AX\d+\]=(\S+))"), cec_value(R"(\$AN_CEC\[(\d+),(\d+)\]=(\S+))"),
      cec_parameter(R"(\$AN_CEC_(\w+)\[(\d+)\]=(\S+))");
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_match(line, m, lec_value)) {
      EXPECT_EQ(std::stoul(m[1]), lec.size());
      lec.push_back(std::stod(m[3])), lec_axis = std::stoi(m[2]);
    } else if (std::regex_match(line, m, lec_parameter)) {
      if (m[1] == "STEP") lec_step = std::stod(m[2]);
      if (m[1] == "MIN") lec_min = std::stod(m[2]);
    } else if (std::regex_match(line, m, cec_value)) {
      cec_values[std::stoi(m[1])].push_back(std::stod(m[3]));
    } else if (std::regex_match(line, m, cec_parameter)) {
      cec[std::stoi(m[2])][m[1]] = m[3];
    }
  }
  return [=](const Axes& q, int direction) {
    Axes c = Axes::Zero();
    const auto la = static_cast<Eigen::Index>(lec_axis - 1);
    c[la] -= equidistant(lec, lec_min, lec_step, q[la]);
    for (const auto& [t, p] : cec) {
      const int table_direction = std::stoi(p.at("DIRECTION"));
      if (table_direction != 0 && table_direction != direction) continue;
      const auto input = static_cast<Eigen::Index>(std::stoi(p.at("INPUT_AXIS").substr(2)) - 1);
      const auto output = static_cast<Eigen::Index>(std::stoi(p.at("OUTPUT_AXIS").substr(2)) - 1);
      c[output] += equidistant(cec_values.at(t), std::stod(p.at("MIN")), std::stod(p.at("STEP")), q[input]);
    }
    return c;
  };
}

// Heidenhain *.COM: a header line, a line of column names, rows by NR; AXISPOS the
// positions of the axis the table is assigned to, a column per axis compensated (the
// value added), BACKLASH the axis' own values for travel the negative way.
Corrections load_heidenhain(const std::string& text, std::size_t axis) {
  std::istringstream in(text);
  std::string line, column;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("BEGIN ", 0), 0U);
  std::getline(in, line);
  std::vector<std::string> columns;
  for (std::istringstream names(line); names >> column;) columns.push_back(column);
  std::map<std::string, std::vector<double>> values;
  while (std::getline(in, line) && line != "[END]") {
    std::istringstream row(line);
    for (const std::string& c : columns) {
      double v = 0;
      row >> v;
      values[c].push_back(v);
    }
  }
  return [values, axis](const Axes& q, int direction) {
    const std::vector<double>& at = values.at("AXISPOS");
    const double step = at[1] - at[0], p = q[static_cast<Eigen::Index>(axis)];
    Axes c = Axes::Zero();
    for (std::size_t j = 0; j < 9; ++j) {
      const std::string name(1, "XYZABCUVW"[j]);
      if (!values.contains(name)) continue;
      const bool own = j == axis;
      c[static_cast<Eigen::Index>(j)] =
          equidistant(own && direction < 0 ? values.at("BACKLASH") : values.at(name), at.front(), step, p);
    }
    return c;
  };
}

// Centroid (version 3, cnc-x.tab): the lines "CNC10 TAB FILE VERSION 3", "AXIS x", "UNITS MM",
// "INTERVAL n", "ENTRIES n", then a row a point from machine home outwards: position, the
// correction travelling forward (up) and in reverse, in the units stated, interpolated
// between points and held beyond them.
Corrections load_centroid(const std::string& text, std::size_t axis) {
  std::istringstream in(text);
  std::string line, word, unit;
  std::getline(in, line);
  EXPECT_EQ(line, "CNC10 TAB FILE VERSION 3");
  std::map<std::string, std::string> header;
  for (int k = 0; k < 4 && std::getline(in, line); ++k) {
    std::istringstream fields(line);
    fields >> word;
    fields >> header[word];
  }
  EXPECT_EQ(header["AXIS"], std::string(1, "XYZABCUVW"[axis]));
  EXPECT_EQ(header["UNITS"], "MM");
  struct Row {
    double at, fwd, rev;
  };
  std::vector<Row> rows;
  for (Row r{}; in >> r.at >> r.fwd >> r.rev;) rows.push_back(r);
  EXPECT_EQ(rows.size(), std::stoul(header["ENTRIES"]));
  EXPECT_EQ(rows.front().at, 0.0) << "from machine home";
  for (std::size_t k = 1; k < rows.size(); ++k)
    EXPECT_EQ(std::abs(rows[k].at - rows[k - 1].at), std::stod(header["INTERVAL"]));
  std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.at < b.at; });
  std::vector<double> fwd, rev;
  for (const Row& r : rows) fwd.push_back(r.fwd), rev.push_back(r.rev);
  const double min = rows.front().at, step = std::stod(header["INTERVAL"]);
  return [=](const Axes& p, int direction) {
    Axes c = Axes::Zero();
    c[static_cast<Eigen::Index>(axis)] =
        equidistant(direction > 0 ? fwd : rev, min, step, p[static_cast<Eigen::Index>(axis)]);
    return c;
  };
}

/// The tool's miss with the axes commanded to q (chain units) plus the corrections (table
/// units), against the perfect machine at q: the tip in machine-axis directions (mm) and the
/// turn about rotary axis `axis` (rad; 0 for a linear one).
struct Miss {
  Eigen::Vector3d tip;
  double turn = 0.0;
};

Miss miss(const model::ForwardModel& f, model::ForwardData& d, const model::ChainQ& q, const Axes& c, std::size_t axis,
          int direction) {
  model::Conditions conditions;
  conditions.temperatures.assign(f.machine().sensors.size(), 20.0);
  model::ChainQ moved = q;
  moved[static_cast<Eigen::Index>(axis)] += 1e-4;
  model::forward(f, d, moved, conditions, false, model::Evaluate::nominal);
  const Eigen::Matrix3d turned = d.R_nominal;
  model::forward(f, d, q, conditions, false, model::Evaluate::nominal);
  const Eigen::Vector3d wanted = d.nominal;
  const Eigen::Matrix3d wanted_turn = d.R_nominal;
  conditions.directions[axis] = direction;  // the others stand in the middle of their play
  model::ChainQ commanded = q;
  for (Eigen::Index j = 0; j < 9; ++j) commanded[j] += j >= 3 ? c[j] * M_PI / 180.0 : c[j];
  model::forward(f, d, commanded, conditions);
  Miss m{d.nominal_chain.oMp.R * (d.actual - wanted), 0.0};
  if (axis >= 3) {
    const Eigen::Vector3d u = kinematics::so3_log(wanted_turn.transpose() * turned).normalized();
    m.turn = u.dot(kinematics::so3_log(wanted_turn.transpose() * d.R_actual));
  }
  return m;
}

double json_number(const std::string& json, const std::string& object, const std::string& key) {
  std::smatch m;
  const std::string inside = object.empty() ? "" : "\"" + object + "\": \\{[^}]*";
  const std::regex r(inside + "\"" + key + "\": (-?[0-9.e+-]+)");
  EXPECT_TRUE(std::regex_search(json, m, r)) << object << "." << key << " in " << json;
  return std::stod(m[1]);
}

struct ExportCase {
  std::string control;
  std::string model;  ///< of samples/machines
  char axis;
  double bound_um;    ///< what the table leaves along its line, at most (interpolation, digits)
  std::string extra;  ///< options
};

const std::string kReadings = " --sensor bed=20 --sensor column=20 --sensor spindle=20";

class ControllerTables : public ::testing::TestWithParam<ExportCase> {};

TEST_P(ControllerTables, ReadBackAsTheControlDoesReproducesTheModelAlongTheAxis) {
  const ExportCase& c = GetParam();
  const std::string dir = temp_dir("controller_tables");
  const std::string table = dir + "/" + c.control + "-" + c.axis + ".tbl";
  const std::string model_path = source_dir() + "/samples/machines/" + c.model + ".yaml";
  const CommandResult r =
      run_command(shell_quote(ccomp_binary()) + " export -m " + shell_quote(model_path) + " --control " + c.control +
                  " --axis " + std::string(1, c.axis) + " -o " + shell_quote(table) + " --json " + c.extra);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_file(table);
  const std::size_t axis = std::string("XYZABCUVW").find(c.axis);
  const bool rotary = axis >= 3;
  Corrections corrections;
  if (c.control == "linuxcnc")
    corrections = load_linuxcnc(text, c.extra.find("--comp-file-type 1") != std::string::npos ? 1 : 0, axis);
  if (c.control == "fanuc") corrections = load_fanuc(text, axis, 0.001);
  if (c.control == "siemens") corrections = load_siemens(text);
  if (c.control == "heidenhain") corrections = load_heidenhain(text, axis);
  if (c.control == "centroid") corrections = load_centroid(text, axis);
  const model::MachineModel machine = sample_machine(c.model);
  const model::ForwardModel f(machine);
  model::ForwardData d(f);
  // The axes in the table's units (mm, deg), and back.
  const double unit = rotary ? M_PI / 180.0 : 1.0;
  auto table_units = [](const model::ChainQ& q) {
    Axes p = q.head<9>();
    p.tail<6>() *= 180.0 / M_PI;
    return p;
  };
  // Its own error: along the axis (um), or its turn (arcsec).
  const double own_scale = rotary ? 180.0 / M_PI * 3600.0 : 1e3;
  auto own = [&](const Miss& m) { return rotary ? m.turn : m.tip[static_cast<Eigen::Index>(axis)]; };
  // Along the line the export took (the other axes at 0, a 100 mm tool), both directions.
  double before = 0, after = 0, whole_before = 0, whole_after = 0;
  const double from = json_number(r.out, "", "from"), to = json_number(r.out, "", "to");
  // Every table is 0 at the reference position: the offset there is the work offset's.
  model::ChainQ reference = model::ChainQ::Zero();
  reference[9] = 100;
  const Miss offset = miss(f, d, reference, corrections(table_units(reference), +1), axis, +1);
  EXPECT_LT(corrections(table_units(reference), +1).norm(), 1e-6);
  for (double p = from; p <= to; p += 0.37)
    for (int direction : {+1, -1}) {
      model::ChainQ q = model::ChainQ::Zero();
      q[static_cast<Eigen::Index>(axis)] = p * unit, q[9] = 100;
      const Miss uncorrected = miss(f, d, q, Axes::Zero(), axis, direction);
      const Miss corrected = miss(f, d, q, corrections(table_units(q), direction), axis, direction);
      before = std::max(before, std::abs(own(uncorrected) - own(offset)));
      after = std::max(after, std::abs(own(corrected) - own(offset)));
      whole_before = std::max(whole_before, (uncorrected.tip - offset.tip).norm());
      whole_after = std::max(whole_after, (corrected.tip - offset.tip).norm());
    }
  before *= own_scale, after *= own_scale, whole_before *= 1e3, whole_after *= 1e3;
  EXPECT_GT(before, 5.0);
  EXPECT_LT(after, c.bound_um) << "before " << before;
  // The export's own figure (sampled every step / 8) is what the control does.
  EXPECT_NEAR(json_number(r.out, "line_own_axis", "max_after_um"), after, 0.05 + 0.05 * after);
  EXPECT_NEAR(json_number(r.out, "line", "max_after_um"), whole_after, 0.05 + 0.05 * whole_after);
  // Siemens' and Heidenhain's cross tables carry the other axes' straightness on the line
  // too (on the geometric model: the full one has the other axes' backlash, which depends
  // on how they last moved, not on this axis).
  if ((c.control == "siemens" || c.control == "heidenhain") && c.model == "hmc-xyzb-geometric" && !rotary) {
    EXPECT_GT(whole_before, before);
    EXPECT_LT(whole_after, c.bound_um + 0.1) << "before " << whole_before;
  }
}

// Bounds: linear interpolation over a step h leaves h^2/8 |e''|. The full HMC's lead
// screws (10-12 mm periods, 1.2-2 um) leave 0.8-1.3 um at LinuxCNC's and Heidenhain's 256
// points (3.5-4 mm), 0.2 um at Siemens' 1000 (1.5 mm) and 3.9 um at Fanuc's 128 (7.5 mm on
// Y); the geometric model (smooth error motions) is held to the digits, Fanuc's to its
// 1 um units.
INSTANTIATE_TEST_SUITE_P(Controls, ControllerTables,
                         ::testing::Values(ExportCase{"linuxcnc", "hmc-xyzb", 'X', 1.5, kReadings},
                                           ExportCase{"linuxcnc", "hmc-xyzb", 'X', 1.5,
                                                      kReadings + " --comp-file-type 1"},
                                           ExportCase{"linuxcnc", "hmc-xyzb-geometric", 'Y', 0.05, ""},
                                           ExportCase{"siemens", "hmc-xyzb", 'X', 0.3, kReadings},
                                           ExportCase{"siemens", "hmc-xyzb-geometric", 'Y', 0.05, ""},
                                           ExportCase{"heidenhain", "hmc-xyzb", 'X', 1.5, kReadings},
                                           ExportCase{"heidenhain", "hmc-xyzb-geometric", 'Z', 0.05, ""},
                                           ExportCase{"fanuc", "hmc-xyzb", 'Y', 4.0, kReadings},
                                           ExportCase{"fanuc", "hmc-xyzb-geometric", 'Z', 0.6, ""},
                                           // Centroid's table runs from machine home (0) to one end
                                           ExportCase{"centroid", "hmc-xyzb", 'X', 0.5, kReadings + " --to 0"},
                                           ExportCase{"centroid", "hmc-xyzb-geometric", 'Y', 0.05, " --from 0"},
                                           // B's angular positioning (arcsec; EBB, 18 urad harmonics): the table
                                           // holds the turn at each point, between them the interpolation
                                           ExportCase{"linuxcnc", "hmc-xyzb-geometric", 'B', 0.05, ""},
                                           ExportCase{"fanuc", "hmc-xyzb-geometric", 'B', 2.0, ""},
                                           ExportCase{"siemens", "hmc-xyzb", 'B', 0.5, kReadings},
                                           ExportCase{"heidenhain", "hmc-xyzb-geometric", 'B', 0.05, ""}),
                         [](const ::testing::TestParamInfo<ExportCase>& param) {
                           std::string name =
                               param.param.control + "_" + std::string(1, param.param.axis) + "_" + param.param.model;
                           if (param.param.extra.find("type 1") != std::string::npos) name += "_type1";
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

struct RefusedExport {
  std::string options;
  int exit_code;
  std::string message;
};

class ControllerTablesRefuse : public ::testing::TestWithParam<RefusedExport> {};

TEST_P(ControllerTablesRefuse, WithTheReason) {
  const RefusedExport& c = GetParam();
  const std::string dir = temp_dir("controller_tables_refuse");
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " export -m " +
                                      shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") + " " +
                                      c.options + " -o " + shell_quote(dir + "/t.tbl"));
  EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
  EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/t.tbl"));
}

INSTANTIATE_TEST_SUITE_P(
    Controls, ControllerTablesRefuse,
    ::testing::Values(RefusedExport{"--control linuxcnc --axis Q", 2, "has no such axis"},
                      RefusedExport{"--control linuxcnc --axis X --at X=3", 2, "the table's own axis"},
                      RefusedExport{"--control linuxcnc --axis X --at Y=1000", 2, "Y travels from -450 to 450"},
                      RefusedExport{"--control fanuc --axis X --fanuc-unit 0.3", 2, "whole number of detection units"},
                      RefusedExport{"--control fanuc --axis X --fanuc-reference-point 1000", 2, "outside Fanuc's"},
                      RefusedExport{"--control fanuc --axis B --from 0 --to 180", 2, "runs over one turn"},
                      RefusedExport{"--control fanuc --axis X --step 1", 2, "more than the 128 points"},
                      RefusedExport{"--control siemens --axis X --at Y=abc", 2, "is not a number"},
                      RefusedExport{"--control siemens --axis X --at Q=1", 2, "has no Q axis"},
                      RefusedExport{"--control heidenhain --axis X --from 5 --to 5", 2, "not a finite range"},
                      RefusedExport{"--control centroid --axis X", 2, "give --from 0 or --to 0"},
                      RefusedExport{"--control centroid --axis X --from -500 --to 500", 2, "starts at machine home"},
                      RefusedExport{"--control centroid --axis X --to 0 --step 2.5", 2, "whole --step"},
                      RefusedExport{"--control centroid --axis B --from 0 --to 360", 2, "linear axis only"},
                      RefusedExport{"--control okuma --axis X", 2, "okuma"}));

TEST(ControllerTablesCli, JsonNeedsTheTableInAFile) {
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " export -m " +
                                      shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") +
                                      " --control linuxcnc --axis X --json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("-o FILE"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ccomp::test

namespace ccomp::test {
namespace {

CommandResult export_table(const std::string& model, const std::string& options, const std::string& path) {
  return run_command(shell_quote(ccomp_binary()) + " export -m " +
                     shell_quote(source_dir() + "/samples/machines/" + model + ".yaml") + " " + options + " -o " +
                     shell_quote(path) + " --json");
}

/// Fanuc's parameter `number` of the file's text.
long fanuc_parameter(const std::string& text, int number) {
  std::smatch m;
  const std::string pattern = "N0" + std::to_string(number) + "A\\d+P(-?\\d+)";
  EXPECT_TRUE(std::regex_search(text, m, std::regex(pattern))) << number;
  return std::stol(m[1]);
}

// A span without 0 has its reference at the end nearest 0, and the table holds there too.
TEST(ControllerTablesFanuc, ASpanWithoutZeroIsReferencedAtItsEndNearestZero) {
  const std::string dir = temp_dir("controller_tables_fanuc_span");
  for (const std::string span : {"--from 100 --to 500", "--from -500 --to -100"}) {
    const CommandResult r = export_table("vmc-xyz", "--control fanuc --axis X " + span, dir + "/x.prm");
    ASSERT_EQ(r.exit_code, 0) << span << r.err;
    const std::string text = read_file(dir + "/x.prm");
    const long reference = fanuc_parameter(text, 3620), first = fanuc_parameter(text, 3621),
               last = fanuc_parameter(text, 3622);
    EXPECT_TRUE(reference == first || reference == last) << span;
    const bool above_zero = span.find("-500") == std::string::npos;
    EXPECT_EQ(json_number(r.out, "", "reference"), json_number(r.out, "", above_zero ? "from" : "to")) << span;
    EXPECT_LT(json_number(r.out, "line_own_axis", "max_after_um"), 1.0) << span;
  }
}

// Compensation points are numbered across the axes: each axis' table has its own.
TEST(ControllerTablesFanuc, AxesTakeDistinctPointNumbers) {
  const std::string dir = temp_dir("controller_tables_fanuc_axes");
  std::vector<std::pair<long, long>> ranges;
  for (const char* axis : {"X", "Y", "Z"}) {
    ASSERT_EQ(export_table("vmc-xyz", std::string("--control fanuc --axis ") + axis, dir + "/t.prm").exit_code, 0);
    const std::string text = read_file(dir + "/t.prm");
    ranges.emplace_back(fanuc_parameter(text, 3621), fanuc_parameter(text, 3622));
  }
  for (std::size_t a = 0; a < ranges.size(); ++a)
    for (std::size_t b = a + 1; b < ranges.size(); ++b)
      EXPECT_TRUE(ranges[a].second < ranges[b].first || ranges[b].second < ranges[a].first) << a << " " << b;
}

// X's backlash is X's: the B table's play (it depends on how B last moved) stays out.
TEST(ControllerTablesFanuc, AnAxisBacklashIsItsOwn) {
  const std::string dir = temp_dir("controller_tables_fanuc_backlash");
  ASSERT_EQ(export_table("hmc-xyzb", "--control fanuc --axis X" + kReadings, dir + "/x.prm").exit_code, 0);
  // hmc-xyzb.yaml: EXX reversal -4 um; B's is -10 urad, ~3 um at the tool.
  EXPECT_EQ(std::abs(fanuc_parameter(read_file(dir + "/x.prm"), 1851)), 4);
}

}  // namespace
}  // namespace ccomp::test
