#include "candidates.hpp"

#include "aliasing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include "ccomp/constants.hpp"
#include "ccomp/model/error_term.hpp"
#include "ccomp/util/interval.hpp"

namespace ccomp::identify::detail {
namespace {

/// Makes `c` a sinusoid of a scanned period in `variable` (mm, deg): cos and sin.
void periodic_in(Candidate& c, std::function<double(const Observation&)> variable) {
  c.basis_count = 2;
  c.basis = [variable](const Observation& o, int k, double period) {
    const double phase = 2 * std::numbers::pi * variable(o) / period;
    return k == 0 ? std::cos(phase) : std::sin(phase);
  };
  c.phase_variable = std::move(variable);
}


/// Reversal candidates of axis `a` where the data approach it both ways: its positioning
/// (or, on a rotary axis, its angle) depends on the direction it came from (backlash, lost
/// motion); and the same varying along the axis (a screw or a worm worn more where it works
/// most: 1 um at one end, 6 um at the other).
void add_reversals(const MeasurementSet& data, const AxisInfo& a, const std::string& own, std::vector<Candidate>& out,
                   std::size_t probe) {
  const std::size_t vi = a.index;
  const auto first = data.observations.empty() ? 0 : data.observations.front().directions[vi];
  if (std::all_of(data.observations.begin(), data.observations.end(),
                  [vi, first](const Observation& o) { return o.directions[vi] == first; }))
    return;
  const char letter = kAxisLetters[vi];
  const std::string v = axis_name(vi);
  const bool rotary = a.rotary;
  const std::string unit = rotary ? "urad" : "um";
  const double file = rotary ? 1e6 : 1e3;  // internal per file unit of the reversal
  Candidate r;
  r.effect = rotary ? fmt::format(
                          "reversal of the {} axis: its angle depends on the direction it turned to (backlash of "
                          "the worm and wheel, a clamp's lost motion)",
                          letter)
                    : fmt::format(
                          "reversal of the {} axis: its position depends on the approach direction (backlash, "
                          "lost motion)",
                          letter);
  r.error = own, r.term = own, r.variable = "v" + v, r.form = "reversal";
  r.probe = probe;
  r.basis = [vi](const Observation& o, int, double) { return 0.5 * o.directions[vi]; };
  r.yaml = [own, v, file, unit](const Eigen::VectorXd& x, double) {
    return fmt::format("{{name: {}, variable: v{}, form: reversal, unit: {}, reversal: {:.4g}, fit: true}}", own, v,
                       unit, file * x[0]);
  };
  out.push_back(r);
  // Varying along the axis: r(u) = r0 + r1 u, u the axis' position (mm, or deg on a rotary axis).
  Candidate g = r;
  g.effect = fmt::format("reversal of the {} axis that changes along its travel (a {} worn more where it works most)",
                         letter, rotary ? "worm" : "screw");
  g.variable = "v" + v + "," + v;
  g.basis_count = 2;
  const double per = rotary ? kRadPerDeg : 1.0;  // internal units of the position per file unit
  g.basis = [vi, per](const Observation& o, int k, double) {
    return 0.5 * o.directions[vi] * (k == 0 ? 1.0 : o.q[static_cast<Eigen::Index>(vi)] / per);
  };
  // (x[1] is per mm, or per deg, of the position, as the model file's r1.)
  g.yaml = [own, v, file, unit](const Eigen::VectorXd& x, double) {
    return fmt::format(
        "{{name: {}, variable: v{}, form: reversal, along: {}, unit: {}, reversal: [{:.4g}, {:.4g}], fit: true}}", own,
        v, v, unit, file * x[0], file * x[1]);
  };
  out.push_back(g);
}

/// A smooth error of axis `a`'s carriage in `component` (a translation) over its own
/// position u and another axis' w, beyond linear (a table overhang sagging with x^2 the
/// further it reaches, a guideway bending under a load), as two tensor-product polynomials
/// of low order: quadratic in u and linear in w (sum c_i1 u^i w, i <= 2), or linear in u and
/// quadratic in w (sum c_ij u^i w^j, i <= 1, j <= 2). (One of both orders at once would have
/// columns the data barely tell apart, and values no machine has.) The model file's term is
/// the whole polynomial; the fit takes its linear part where the data determine it.
Candidate smooth_two_variable(const AxisInfo& a, const AxisInfo& w, int component, std::size_t probe,
                              bool quadratic_in_own) {
  const std::string term = term_name(component, a.link, false);
  Candidate x;
  x.effect = fmt::format(
      "{} of the {} carriage that changes with the {} position and {} (an overhang sagging, a guideway bending "
      "under a load)",
      component == a.own ? "positioning" : "straightness", kAxisLetters[a.index], kAxisLetters[w.index],
      quadratic_in_own ? std::string("with the square of its own") : fmt::format("with the square of the {}'s", kAxisLetters[w.index]));
  x.error = term, x.term = term, x.variable = axis_name(a.index) + "," + axis_name(w.index);
  x.form = "interaction";
  x.probe = probe;
  const auto ai = static_cast<Eigen::Index>(a.index), wi = static_cast<Eigen::Index>(w.index);
  // Only the columns beyond linear: the linear cross-axis candidate has the others, and a
  // base's squareness takes w alone, which would leave its coefficient to the noise.
  if (quadratic_in_own) {
    x.basis = [ai, wi](const Observation& o, int, double) { return o.q[ai] * o.q[ai] * o.q[wi]; };
    x.yaml = [term, other = axis_name(w.index)](const Eigen::VectorXd& c, double) {
      return fmt::format(
          "{{name: {}, form: cross_axis, other: {}, unit: um, coefficients: [[0], [0], [{:.4g}]], fit: true}}", term,
          other, 1e3 * c[0]);
    };
  } else {
    x.basis_count = 2;
    x.basis = [ai, wi](const Observation& o, int k, double) {
      return (k == 0 ? 1.0 : o.q[ai]) * o.q[wi] * o.q[wi];
    };
    x.yaml = [term, other = axis_name(w.index)](const Eigen::VectorXd& c, double) {
      return fmt::format(
          "{{name: {}, form: cross_axis, other: {}, unit: um, coefficients: [[0, {:.4g}], [0, {:.4g}]], fit: true}}",
          term, other, 1e3 * c[0], 1e3 * c[1]);
    };
  }
  return x;
}
}  // namespace

/// A candidate's columns at a scanned value (a period, a time constant): its probe's
/// column times each basis function, on the probe's rows (`out` has a row per probe row),
/// or on every reading (`out` has n rows, zero off the probe's rows).
void candidate_columns(const Candidate& c, const Probe& p, const MeasurementSet& data, double value, bool every_row,
                       Eigen::Ref<Eigen::MatrixXd> out) {
  for (std::size_t i = 0; i < p.rows.size(); ++i) {
    const Eigen::Index row = p.rows[i];
    const Observation& o = data.observations[static_cast<std::size_t>(row)];
    for (int k = 0; k < c.basis_count; ++k)
      out(every_row ? row : static_cast<Eigen::Index>(i), k) = p.g[row] * c.basis(o, k, value);
  }
}

std::string axis_name(std::size_t i) {
  return std::string(1, static_cast<char>(std::tolower(kAxisLetters[i])));
}

/// An axis' position in a reading, in the file's units (mm, deg): a linear axis' slide
/// position (Z without the tool length), a rotary axis' angle.
double axis_value(const Observation& o, const AxisInfo& a) {
  return file_axis_value(o, a.index, a.rotary);
}

std::vector<AxisInfo> axes_of(const model::MachineModel& mm, const MeasurementSet& data) {
  std::vector<AxisInfo> axes;
  for (const auto* chain : {&mm.workpiece_chain, &mm.tool_chain})
    for (const model::LinkSpec& l : *chain) {
      if (!l.axis) continue;
      AxisInfo a;
      a.index = kAxisLetters.find(*l.axis);
      a.link = l.name;
      a.rotary = mm.axis(*l.axis) && mm.axis(*l.axis)->type == model::AxisType::rotary;
      Eigen::Index along = 0;
      l.direction.cwiseAbs().maxCoeff(&along);
      a.own = static_cast<int>(along) + (a.rotary ? 3 : 0);
      const auto qi = static_cast<Eigen::Index>(a.index);
      util::Interval reach;
      for (const Observation& o : data.observations) reach.add(axis_value(o, a));
      a.from = reach.lo, a.to = reach.hi;
      // The median spacing between consecutive readings that differ along this axis only.
      std::vector<double> steps, positions;  // and the positions such moves visit
      for (std::size_t i = 1; i < data.observations.size(); ++i) {
        const model::ChainQ d = data.observations[i].q - data.observations[i - 1].q;
        const double travel = std::abs(d[qi]);
        if (travel > 1e-9 && d.norm() - travel < 1e-9 * (1.0 + travel)) {
          steps.push_back(a.rotary ? travel / kRadPerDeg : travel);
          positions.push_back(axis_value(data.observations[i - 1], a));
          positions.push_back(axis_value(data.observations[i], a));
        }
      }
      if (steps.empty()) {
        // No reading moves along this axis alone (a sphere probed as B turns moves X and Z
        // with it): the spacing of the distinct positions the data visit.
        std::vector<double> visited;
        for (const Observation& o : data.observations) visited.push_back(axis_value(o, a));
        std::sort(visited.begin(), visited.end());
        for (std::size_t i = 1; i < visited.size(); ++i)
          if (visited[i] - visited[i - 1] > 1e-9 * (1.0 + std::abs(visited[i]))) {
            steps.push_back(visited[i] - visited[i - 1]);
            positions.push_back(visited[i]);
          }
      }
      if (!steps.empty()) {
        std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
        a.step = steps[steps.size() / 2];
        a.on_lattice = on_lattice(positions, a.step);
      }
      axes.push_back(a);
    }
  return axes;
}

/// A term's ISO name: "EXX", a location error "EC0X".
std::string term_name(int component, const std::string& link, bool location) {
  return fmt::format("E{}{}{}", kComponents[static_cast<std::size_t>(component)], location ? "0" : "", link);
}

/// The candidate effects the data can show, with the probes (links and components) they enter.
std::vector<Candidate> candidate_library(const model::MachineModel& mm, const MeasurementSet& data,
                                         const std::vector<AxisInfo>& axes, std::vector<Probe>& probes) {
  const auto& tool_chain = mm.tool_chain;
  std::string spindle;  // the tool side's last link before the tool: where the spindle tilts and drifts
  for (const model::LinkSpec& l : tool_chain)
    if (!l.tool) spindle = l.name;
  auto probe = [&](const std::string& link, int component,
                   model::ErrorPlacement placement = model::ErrorPlacement::motion) {
    for (std::size_t i = 0; i < probes.size(); ++i)
      if (probes[i].link == link && probes[i].component == component && probes[i].placement == placement) return i;
    probes.push_back(Probe{link, component, placement, {}, {}, {}});
    return probes.size() - 1;
  };
  const auto location = model::ErrorPlacement::location;
  auto position = [](const Observation& o, const AxisInfo& a) {  // internal units: mm, rad
    return o.q[static_cast<Eigen::Index>(a.index)];
  };
  auto varies = [&](auto get) {
    util::Interval range;
    for (const Observation& o : data.observations) range.add(get(o));
    return range.hi > range.lo + 1e-12;
  };
  const bool tool_length_varies =
      varies([](const Observation& o) { return o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]; });
  // A sensor is a candidate variable when every reading has it and it changes: the model's
  // own, and any other T_<name> column of the files (a suggestion then adds the sensor).
  auto read_and_varies = [&](std::size_t sensor) {
    for (const Observation& o : data.observations)
      if (sensor >= o.temperatures.size() || std::isnan(o.temperatures[sensor])) return false;
    return varies([sensor](const Observation& o) { return o.temperatures[sensor]; });
  };
  const bool time_varies = varies([](const Observation& o) { return o.time; });
  auto unit = [](int component) { return component < 3 ? "um" : "urad"; };
  auto file_value = [](int component, double internal) { return internal * (component < 3 ? 1e3 : 1e6); };
  auto name = term_name;

  std::vector<Candidate> candidates;
  for (const AxisInfo& a : axes) {
    const std::string v = axis_name(a.index);
    const double span = a.to - a.from;
    if (!(span > 0)) continue;
    const std::string own = name(a.own, a.link, false);
    if (!a.rotary) {
      // Periodic positioning error: the lead screw's pitch, or the scale's.
      Candidate c;
      c.effect = fmt::format("periodic error of the {} axis' positioning (lead-screw pitch or scale pitch)",
                             kAxisLetters[a.index]);
      c.error = own, c.term = own, c.variable = v, c.form = "periodic";
      c.probe = probe(a.link, a.own);
      periodic_in(c, [&a, position](const Observation& o) { return position(o, a); });
      // Readings every step s along the axis (on a lattice) cannot tell a period from its
      // aliases 1 / (k / s +- 1 / P): the scan covers two steps (Nyquist) and up, and what it
      // finds is said to be possibly aliased (aliasing.hpp). With ISO 230-2's irregular
      // targets no period aliases another: it goes on down to a quarter of the spacing.
      // A period is named only where the data cover enough of its cycles to tell it from a
      // slow curve (a shape the library lacks, a thermal drift seen along a line): four.
      c.scan_from = std::max(2.0, (a.on_lattice ? 2.0 : 0.25) * a.step), c.scan_to = span / kCyclesForAPeriod;
      if (a.on_lattice) {
        c.lattice_step = a.step, c.shortest_period = 2.0, c.period_unit = "mm";
        c.settling_run = fmt::format("a laser line along {}", kAxisLetters[a.index]);
      }
      // Two frequencies per peak width (1 / span): a peak is seen at 80% of its height or
      // better, and refined between its neighbours.
      c.scan_points = static_cast<int>(std::clamp(2.0 * span / c.scan_from, 50.0, 6000.0));
      c.yaml = [own, component = a.own, file_value](const Eigen::VectorXd& x, double period) {
        return fmt::format(
            "{{name: {}, form: periodic, period: {:.6g} mm, unit: um, harmonics: [[{:.4g}, "
            "{:.4g}]], fit: true}}",
            own, period, file_value(component, x[0]), file_value(component, x[1]));
      };
      candidates.push_back(c);
      add_reversals(data, a, own, candidates, probe(a.link, a.own));
      // Higher order: positioning and straightness, one degree above what the model has.
      for (int component = 0; component < 3; ++component) {
        const std::string term = name(component, a.link, false);
        int degree = 2;
        for (const model::ErrorTermSpec& t : mm.terms)
          if (t.iso == term && t.shape.form == model::TermForm::polynomial) degree = std::max(degree, t.shape.order);
        const int power = degree + 1;
        Candidate h;
        h.effect = fmt::format("{} of the {} axis of higher order (degree {})",
                               component == a.own ? "positioning error" : "straightness", kAxisLetters[a.index], power);
        h.error = term, h.term = term, h.variable = v, h.form = "polynomial";
        h.probe = probe(a.link, component);
        h.basis = [&a, position, power](const Observation& o, int, double) { return std::pow(position(o, a), power); };
        h.yaml = [term, power, file_value, component](const Eigen::VectorXd& x, double) {
          std::string coefficients;
          for (int k = 0; k < power; ++k) coefficients += "0, ";
          return fmt::format("{{name: {}, form: polynomial, unit: um, coefficients: [{}{:.4g}], fit: true}}", term,
                             coefficients, file_value(component, x[0]));
        };
        candidates.push_back(h);
      }
      // A local defect of the guideway or the scale (a bump, a scale joint): a bell at a
      // scanned place along the axis, in each direction, at two widths (a short defect and
      // a longer one, 1/64 and 1/24 of the travel as one standard deviation).
      for (int component = 0; component < 3; ++component)
        for (const double width : {span / 64.0, span / 24.0}) {
          if (width < 2.0 * a.step) continue;  // a bell narrower than the readings' spacing is not seen
          const std::string term = name(component, a.link, false);
          Candidate b;
          b.effect = fmt::format(
              "a local defect of the {} axis' {} ({} wide): a bump in one place, not a shape of "
              "the whole travel",
              kAxisLetters[a.index],
              component == a.own ? "positioning (a scale joint, a damaged screw)" : "straightness (a guideway's bump)",
              fmt::format("{:.3g} mm", 4 * width));
          b.error = term, b.term = term, b.variable = v, b.form = "bump";
          b.probe = probe(a.link, component);
          b.basis = [&a, position, width](const Observation& o, int, double at) {
            const double u = (position(o, a) - at) / width;
            return std::exp(-0.5 * u * u);
          };
          b.scan_from = a.from, b.scan_to = a.to, b.scan_spacing = Candidate::Spacing::linear;
          b.phase_variable = [&a, position](const Observation& o) { return position(o, a); };
          b.reach = 5.0 * width;
          b.scan_points = static_cast<int>(std::clamp(2.0 * span / width, 20.0, 400.0));  // two per width
          b.yaml = [term, file_value, component, width](const Eigen::VectorXd& x, double at) {
            return fmt::format(
                "{{name: {}, form: bump, at: {:.6g} mm, width: {:.4g} mm, unit: um, amplitude: {:.4g}, "
                "fit: true}}",
                term, at, width, file_value(component, x[0]));
          };
          candidates.push_back(b);
        }
      // Squareness: the axis' line turned about the other two, where the reference frame
      // leaves it free (Z's line is its primary axis, Y's lies in its Z-Y plane).
      for (int component = 3; component < 6; ++component) {
        if (component == a.own + 3 || model::frame_fixes_line_turn(kAxisLetters[a.index], component)) continue;
        const std::string term = name(component, a.link, true);
        Candidate s;
        s.effect = fmt::format("out-of-squareness of the {} axis (its line of motion turned about {})",
                               kAxisLetters[a.index], kComponents[static_cast<std::size_t>(component - 3)]);
        s.error = term, s.term = term, s.variable = v, s.form = "polynomial";
        s.probe = probe(a.link, component, location);
        // A constant tilt of the axis' line: a squareness (EC0X).
        s.basis = [](const Observation&, int, double) { return 1.0; };
        s.yaml = [term, file_value, component](const Eigen::VectorXd& x, double) {
          return fmt::format("{{name: {}, value: {:.4g}, unit: urad, fit: true}}", term, file_value(component, x[0]));
        };
        candidates.push_back(s);
      }
      // Scale expansion: the positioning grows with the temperature of a sensor.
      for (std::size_t sensor = 0; sensor < data.sensors.size(); ++sensor) {
        if (!read_and_varies(sensor)) continue;
        Candidate e;
        e.effect = fmt::format(
            "thermal expansion of the {} axis' scale with {} (the error grows with the position "
            "and the temperature)",
            kAxisLetters[a.index], data.sensors[sensor]);
        e.error = own, e.term = own, e.variable = v + ",T_" + data.sensors[sensor], e.form = "interaction";
        e.probe = probe(a.link, a.own);
        e.basis = [&a, position, sensor](const Observation& o, int, double) {
          return position(o, a) * (o.temperatures[sensor] - 20.0);
        };
        e.yaml = [own, sensor_name = data.sensors[sensor]](const Eigen::VectorXd& x, double) {
          return fmt::format(
              "{{name: {}, form: scale_expansion, temperature: T_{}, coefficient: {:.4g} /degC, "
              "fit: true}}",
              own, sensor_name, x[0]);
        };
        candidates.push_back(e);
      }
      // Cross-axis: an error motion of this axis that varies with another axis' position.
      for (const AxisInfo& w : axes) {
        if (w.rotary || w.index == a.index || !(w.to > w.from)) continue;
        for (int component = 0; component < 6; ++component) {
          const std::string term = name(component, a.link, false);
          Candidate x;
          x.effect = fmt::format(
              "{} of the {} carriage that changes with the {} position (load, overhang: a 2-D Abbe "
              "error)",
              component < 3 ? "straightness/positioning" : "angular error motion", kAxisLetters[a.index],
              kAxisLetters[w.index]);
          x.error = term, x.term = term, x.variable = v + "," + axis_name(w.index), x.form = "interaction";
          x.probe = probe(a.link, component);
          x.basis_count = 2;
          x.basis = [&a, &w, position](const Observation& o, int k, double) {
            return k == 0 ? position(o, w) : position(o, a) * position(o, w);
          };
          x.yaml = [term, component, file_value, other = axis_name(w.index), unit](const Eigen::VectorXd& coefficient,
                                                                                   double) {
            return fmt::format(
                "{{name: {}, form: cross_axis, other: {}, unit: {}, coefficients: [[{:.4g}], "
                "[{:.4g}]], fit: true}}",
                term, other, unit(component), file_value(component, coefficient[0]),
                file_value(component, coefficient[1]));
          };
          candidates.push_back(x);
        }
        for (int component = 0; component < 3; ++component)
          for (const bool quadratic_in_own : {true, false})
            candidates.push_back(smooth_two_variable(a, w, component, probe(a.link, component), quadratic_in_own));
      }
    } else {
      // The table: harmonics of its error motions, its worm wheel, tilt and eccentricity.
      for (int component = 0; component < 6; ++component) {
        const std::string term = name(component, a.link, false);
        for (int harmonic = 1; harmonic <= 3; ++harmonic) {
          Candidate h;
          h.effect = fmt::format("error motion {} of the {} table, {} per turn", term, kAxisLetters[a.index],
                                 harmonic == 1   ? "once"
                                 : harmonic == 2 ? "twice"
                                                 : "three times");
          h.error = term, h.term = term, h.variable = v, h.form = "harmonic", h.period = 360.0 / harmonic;
          h.probe = probe(a.link, component);
          h.basis_count = 2;
          h.basis = [&a, position, harmonic](const Observation& o, int k, double) {
            return k == 0 ? std::cos(harmonic * position(o, a)) : std::sin(harmonic * position(o, a));
          };
          h.yaml = [term, harmonic, file_value, component, unit](const Eigen::VectorXd& x, double) {
            return fmt::format(
                "{{name: {}, form: periodic, period: {:g} deg, unit: {}, harmonics: [[{:.4g}, "
                "{:.4g}]], fit: true}}",
                term, 360.0 / harmonic, unit(component), file_value(component, x[0]), file_value(component, x[1]));
          };
          candidates.push_back(h);
        }
      }
      Candidate w;
      w.effect =
          fmt::format("periodic indexing error of the {} table (a worm wheel's tooth period)", kAxisLetters[a.index]);
      w.error = own, w.term = own, w.variable = v, w.form = "periodic";
      w.probe = probe(a.link, a.own);
      periodic_in(w, [&a, position](const Observation& o) { return position(o, a) / kRadPerDeg; });
      w.scan_from = std::max(1.0, (a.on_lattice ? 2.0 : 0.25) * a.step);
      w.scan_to = std::min(90.0, span / kCyclesForAPeriod);
      if (a.on_lattice) {
        w.lattice_step = a.step, w.shortest_period = 1.0, w.period_unit = "deg";
        w.settling_run = fmt::format("the table probed as {} turns", kAxisLetters[a.index]);
      }
      w.scan_points = static_cast<int>(std::clamp(2.0 * span / w.scan_from, 50.0, 6000.0));
      w.yaml = [own, file_value, component = a.own](const Eigen::VectorXd& x, double period) {
        return fmt::format(
            "{{name: {}, form: periodic, period: {:.6g} deg, unit: urad, harmonics: [[{:.4g}, "
            "{:.4g}]], fit: true}}",
            own, period, file_value(component, x[0]), file_value(component, x[1]));
      };
      candidates.push_back(w);
      add_reversals(data, a, own, candidates, probe(a.link, a.own));
      for (int component = 0; component < 6; ++component) {
        // Along or about its own line a rotary axis' location changes nothing.
        if (component == a.own || component == a.own - 3) continue;
        const std::string term = name(component, a.link, true);
        Candidate l;
        l.effect = component < 3 ? fmt::format("the {} axis' centre is off in {} (eccentricity, location)",
                                               kAxisLetters[a.index], kComponents[static_cast<std::size_t>(component)])
                                 : fmt::format("the {} axis is tilted about {}", kAxisLetters[a.index],
                                               kComponents[static_cast<std::size_t>(component - 3)]);
        l.error = term, l.term = term, l.variable = v, l.form = "polynomial";
        l.probe = probe(a.link, component, location);
        l.basis = [](const Observation&, int, double) { return 1.0; };
        l.yaml = [term, file_value, component, unit](const Eigen::VectorXd& x, double) {
          return fmt::format("{{name: {}, value: {:.4g}, unit: {}, fit: true}}", term, file_value(component, x[0]),
                             unit(component));
        };
        candidates.push_back(l);
      }
    }
  }
  // The tool: a tilt of the spindle shows as an error growing with the tool length (Abbe).
  if (!spindle.empty() && tool_length_varies) {
    for (int component = 3; component < 5; ++component) {
      const std::string term = name(component, spindle, true);
      Candidate t;
      t.effect = fmt::format("the spindle is tilted about {}: the error grows with the tool length (Abbe arm)",
                             kComponents[static_cast<std::size_t>(component - 3)]);
      t.error = term, t.term = term, t.variable = "L", t.form = "linear";
      t.probe = probe(spindle, component);
      t.basis = [](const Observation&, int, double) { return 1.0; };
      t.yaml = [term, file_value, component](const Eigen::VectorXd& x, double) {
        return fmt::format("{{name: {}, value: {:.4g}, unit: urad, fit: true}}", term, file_value(component, x[0]));
      };
      candidates.push_back(t);
    }
  }
  // Heat: a drift of the tool against the workpiece with a sensor's temperature, or in time.
  if (!spindle.empty()) {
    for (int component = 0; component < 3; ++component) {
      const std::string term = name(component, spindle, false);
      for (std::size_t sensor = 0; sensor < data.sensors.size(); ++sensor) {
        if (!read_and_varies(sensor)) continue;
        Candidate d;
        d.effect = fmt::format("thermal drift in {} with the temperature at {}",
                               kComponents[static_cast<std::size_t>(component)], data.sensors[sensor]);
        d.error = "thermal", d.term = term, d.variable = "T_" + data.sensors[sensor], d.form = "linear";
        d.probe = probe(spindle, component);
        d.basis = [sensor](const Observation& o, int, double) { return o.temperatures[sensor] - 20.0; };
        d.yaml = [term, sensor_name = data.sensors[sensor], file_value, component](const Eigen::VectorXd& x, double) {
          return fmt::format(
              "{{name: {}, variable: T_{}, form: thermal, unit: um, coefficient: {:.4g}, fit: "
              "true}}",
              term, sensor_name, file_value(component, x[0]));
        };
        candidates.push_back(d);
      }
      if (time_varies) {
        Candidate w;
        w.effect = fmt::format("warm-up drift in {}: first order in time since the start",
                               kComponents[static_cast<std::size_t>(component)]);
        w.error = "thermal", w.term = term, w.variable = "t", w.form = "exponential";
        w.probe = probe(spindle, component);
        w.basis = [](const Observation& o, int, double tau) { return 1.0 - std::exp(-o.time / tau); };
        w.scan_from = 120.0, w.scan_to = 4 * 3600.0, w.scan_points = 60;
        w.scan_spacing = Candidate::Spacing::logarithmic;
        w.yaml = [term, file_value, component](const Eigen::VectorXd& x, double tau) {
          return fmt::format(
              "{{name: {}, variable: t, form: warmup, unit: um, amplitude: {:.4g}, time_constant: "
              "{:.0f} s, fit: true}}",
              term, file_value(component, x[0]), tau);
        };
        candidates.push_back(w);
      }
    }
  }
  return candidates;
}

}  // namespace ccomp::identify::detail
