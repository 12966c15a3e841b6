#include "candidate_families.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ccomp/constants.hpp"
#include "ccomp/model/error_term.hpp"

namespace ccomp::identify::detail {
namespace {

/// An axis' position in a reading, in internal units (mm, rad).
double position(const Observation& o, const AxisInfo& a) { return o.q[static_cast<Eigen::Index>(a.index)]; }
/// The unit a component's term is written in: um for a translation, urad for a turn.
const char* unit_of(int component) { return component < 3 ? "um" : "urad"; }
/// An internal value (mm, rad) in its component's file unit.
double file_value(int component, double internal) { return internal * (component < 3 ? 1e3 : 1e6); }

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

/// How a periodic error of an axis' own motion is scanned and written: in the axis' unit.
struct PeriodicScan {
  double per_unit = 1.0;          ///< internal units per file unit of the position (1 mm; rad per deg)
  double shortest = 2.0;          ///< the shortest period a mechanism of the kind has (mm, deg)
  double longest = 1e300;         ///< the longest scanned (deg: a quarter turn)
  const char* unit = "mm";        ///< the position's unit
  const char* value_unit = "um";  ///< the error's unit in the model file
  std::string settling_run;       ///< the run that tells a period from its aliases
};

/// A periodic error of axis `a`'s own motion, its period scanned.
Candidate scanned_period(LibraryContext& ctx, const AxisInfo& a, std::string effect, const PeriodicScan& scan) {
  const std::string own = term_name(a.own, a.link, false);
  const double span = a.to - a.from;
  Candidate c;
  c.effect = std::move(effect);
  c.error = own, c.term = own, c.variable = axis_name(a.index), c.form = "periodic";
  c.probe = ctx.probe(a.link, a.own);
  periodic_in(c, [&a, per = scan.per_unit](const Observation& o) { return position(o, a) / per; });
  // Readings every step s along the axis (on a lattice) cannot tell a period from its
  // aliases 1 / (k / s +- 1 / P): the scan covers two steps (Nyquist) and up, and what it
  // finds is said to be possibly aliased (aliasing.hpp). With ISO 230-2's irregular
  // targets no period aliases another: it goes on down to a quarter of the spacing.
  // A period is named only where the data cover enough of its cycles to tell it from a
  // slow curve (a shape the library lacks, a thermal drift seen along a line): four.
  c.scan_from = std::max(scan.shortest, (a.on_lattice ? 2.0 : 0.25) * a.step);
  c.scan_to = std::min(scan.longest, span / kCyclesForAPeriod);
  if (a.on_lattice) {
    c.lattice_step = a.step, c.shortest_period = scan.shortest, c.period_unit = scan.unit;
    c.settling_run = scan.settling_run;
  }
  // Two frequencies per peak width (1 / span): a peak is seen at 80% of its height or
  // better, and refined between its neighbours.
  c.scan_points = static_cast<int>(std::clamp(2.0 * span / c.scan_from, 50.0, 6000.0));
  c.yaml = [own, component = a.own, unit = std::string(scan.unit), value_unit = std::string(scan.value_unit)](
               const Eigen::VectorXd& x, double period) {
    return fmt::format(
        "{{name: {}, form: periodic, period: {:.6g} {}, unit: {}, harmonics: [[{:.4g}, "
        "{:.4g}]], fit: true}}",
        own, period, unit, value_unit, file_value(component, x[0]), file_value(component, x[1]));
  };
  return c;
}

// Periodic positioning error: the lead screw's pitch, or the scale's.
void screw_pitch(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  out.push_back(scanned_period(
      ctx, a,
      fmt::format("periodic error of the {} axis' positioning (lead-screw pitch or scale pitch)", kAxisLetters[a.index]),
      PeriodicScan{1.0, 2.0, 1e300, "mm", "um", fmt::format("a laser line along {}", kAxisLetters[a.index])}));
}

void reversal(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  add_reversals(ctx.data, a, term_name(a.own, a.link, false), out, ctx.probe(a.link, a.own));
}

// Positioning and straightness of higher order: one degree above what the model has.
void higher_order(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  for (int component = 0; component < 3; ++component) {
    const std::string term = term_name(component, a.link, false);
    int degree = 2;
    for (const model::ErrorTermSpec& t : ctx.mm.terms)
      if (t.iso == term && t.shape.form == model::TermForm::polynomial) degree = std::max(degree, t.shape.order);
    const int power = degree + 1;
    Candidate h;
    h.effect = fmt::format("{} of the {} axis of higher order (degree {})",
                           component == a.own ? "positioning error" : "straightness", kAxisLetters[a.index], power);
    h.error = term, h.term = term, h.variable = axis_name(a.index), h.form = "polynomial";
    h.probe = ctx.probe(a.link, component);
    h.basis = [&a, power](const Observation& o, int, double) { return std::pow(position(o, a), power); };
    h.yaml = [term, power, component](const Eigen::VectorXd& x, double) {
      std::string coefficients;
      for (int k = 0; k < power; ++k) coefficients += "0, ";
      return fmt::format("{{name: {}, form: polynomial, unit: um, coefficients: [{}{:.4g}], fit: true}}", term,
                         coefficients, file_value(component, x[0]));
    };
    out.push_back(h);
  }
}

// A local defect of the guideway or the scale (a bump, a scale joint): a bell at a scanned
// place along the axis, in each direction, at two widths (a short defect and a longer one,
// 1/64 and 1/24 of the travel as one standard deviation).
void local_defect(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  const double span = a.to - a.from;
  for (int component = 0; component < 3; ++component)
    for (const double width : {span / 64.0, span / 24.0}) {
      if (width < 2.0 * a.step) continue;  // a bell narrower than the readings' spacing is not seen
      const std::string term = term_name(component, a.link, false);
      Candidate b;
      b.effect = fmt::format(
          "a local defect of the {} axis' {} ({} wide): a bump in one place, not a shape of "
          "the whole travel",
          kAxisLetters[a.index],
          component == a.own ? "positioning (a scale joint, a damaged screw)" : "straightness (a guideway's bump)",
          fmt::format("{:.3g} mm", 4 * width));
      b.error = term, b.term = term, b.variable = axis_name(a.index), b.form = "bump";
      b.probe = ctx.probe(a.link, component);
      b.basis = [&a, width](const Observation& o, int, double at) {
        const double u = (position(o, a) - at) / width;
        return std::exp(-0.5 * u * u);
      };
      b.scan_from = a.from, b.scan_to = a.to, b.scan_spacing = Candidate::Spacing::linear;
      b.phase_variable = [&a](const Observation& o) { return position(o, a); };
      b.reach = 5.0 * width;
      b.scan_points = static_cast<int>(std::clamp(2.0 * span / width, 20.0, 400.0));  // two per width
      b.yaml = [term, component, width](const Eigen::VectorXd& x, double at) {
        return fmt::format(
            "{{name: {}, form: bump, at: {:.6g} mm, width: {:.4g} mm, unit: um, amplitude: {:.4g}, "
            "fit: true}}",
            term, at, width, file_value(component, x[0]));
      };
      out.push_back(b);
    }
}

// Squareness: the axis' line turned about the other two, where the reference frame leaves
// it free (Z's line is its primary axis, Y's lies in its Z-Y plane).
void squareness(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  for (int component = 3; component < 6; ++component) {
    if (component == a.own + 3 || model::frame_fixes_line_turn(kAxisLetters[a.index], component)) continue;
    const std::string term = term_name(component, a.link, true);
    Candidate s;
    s.effect = fmt::format("out-of-squareness of the {} axis (its line of motion turned about {})",
                           kAxisLetters[a.index], kComponents[static_cast<std::size_t>(component - 3)]);
    s.error = term, s.term = term, s.variable = axis_name(a.index), s.form = "polynomial";
    s.probe = ctx.probe(a.link, component, model::ErrorPlacement::location);
    // A constant tilt of the axis' line: a squareness (EC0X).
    s.basis = [](const Observation&, int, double) { return 1.0; };
    s.yaml = [term, component](const Eigen::VectorXd& x, double) {
      return fmt::format("{{name: {}, value: {:.4g}, unit: urad, fit: true}}", term, file_value(component, x[0]));
    };
    out.push_back(s);
  }
}

// Scale expansion: the positioning grows with the temperature of a sensor.
void scale_expansion(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  const std::string own = term_name(a.own, a.link, false);
  for (std::size_t sensor = 0; sensor < ctx.data.sensors.size(); ++sensor) {
    if (!ctx.sensor_varies(sensor)) continue;
    Candidate e;
    e.effect = fmt::format(
        "thermal expansion of the {} axis' scale with {} (the error grows with the position "
        "and the temperature)",
        kAxisLetters[a.index], ctx.data.sensors[sensor]);
    e.error = own, e.term = own, e.variable = axis_name(a.index) + ",T_" + ctx.data.sensors[sensor];
    e.form = "interaction";
    e.probe = ctx.probe(a.link, a.own);
    e.basis = [&a, sensor](const Observation& o, int, double) {
      return position(o, a) * (o.temperatures[sensor] - 20.0);
    };
    e.yaml = [own, sensor_name = ctx.data.sensors[sensor]](const Eigen::VectorXd& x, double) {
      return fmt::format(
          "{{name: {}, form: scale_expansion, temperature: T_{}, coefficient: {:.4g} /degC, "
          "fit: true}}",
          own, sensor_name, x[0]);
    };
    out.push_back(e);
  }
}

// Cross-axis: an error motion of this axis that varies with another axis' position, linear
// in both, and smooth beyond linear (smooth_two_variable).
void cross_axis(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo> axes, std::vector<Candidate>& out) {
  for (const AxisInfo& w : axes) {
    if (w.rotary || w.index == a.index || !(w.to > w.from)) continue;
    for (int component = 0; component < 6; ++component) {
      const std::string term = term_name(component, a.link, false);
      Candidate x;
      x.effect = fmt::format(
          "{} of the {} carriage that changes with the {} position (load, overhang: a 2-D Abbe "
          "error)",
          component < 3 ? "straightness/positioning" : "angular error motion", kAxisLetters[a.index],
          kAxisLetters[w.index]);
      x.error = term, x.term = term, x.variable = axis_name(a.index) + "," + axis_name(w.index);
      x.form = "interaction";
      x.probe = ctx.probe(a.link, component);
      x.basis_count = 2;
      x.basis = [&a, &w](const Observation& o, int k, double) {
        return k == 0 ? position(o, w) : position(o, a) * position(o, w);
      };
      x.yaml = [term, component, other = axis_name(w.index)](const Eigen::VectorXd& coefficient, double) {
        return fmt::format(
            "{{name: {}, form: cross_axis, other: {}, unit: {}, coefficients: [[{:.4g}], "
            "[{:.4g}]], fit: true}}",
            term, other, unit_of(component), file_value(component, coefficient[0]),
            file_value(component, coefficient[1]));
      };
      out.push_back(x);
    }
    for (int component = 0; component < 3; ++component)
      for (const bool quadratic_in_own : {true, false})
        out.push_back(smooth_two_variable(a, w, component, ctx.probe(a.link, component), quadratic_in_own));
  }
}

// The table: harmonics of its error motions (eccentric bearings, a wobble), once, twice and
// three times a turn.
void table_harmonics(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  for (int component = 0; component < 6; ++component) {
    const std::string term = term_name(component, a.link, false);
    for (int harmonic = 1; harmonic <= 3; ++harmonic) {
      Candidate h;
      h.effect = fmt::format("error motion {} of the {} table, {} per turn", term, kAxisLetters[a.index],
                             harmonic == 1   ? "once"
                             : harmonic == 2 ? "twice"
                                             : "three times");
      h.error = term, h.term = term, h.variable = axis_name(a.index), h.form = "harmonic";
      h.period = 360.0 / harmonic;
      h.probe = ctx.probe(a.link, component);
      h.basis_count = 2;
      h.basis = [&a, harmonic](const Observation& o, int k, double) {
        return k == 0 ? std::cos(harmonic * position(o, a)) : std::sin(harmonic * position(o, a));
      };
      h.yaml = [term, harmonic, component](const Eigen::VectorXd& x, double) {
        return fmt::format(
            "{{name: {}, form: periodic, period: {:g} deg, unit: {}, harmonics: [[{:.4g}, "
            "{:.4g}]], fit: true}}",
            term, 360.0 / harmonic, unit_of(component), file_value(component, x[0]), file_value(component, x[1]));
      };
      out.push_back(h);
    }
  }
}

// The table's indexing error of a scanned period (a worm wheel's tooth), up to a quarter turn.
void worm_wheel(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  out.push_back(scanned_period(
      ctx, a,
      fmt::format("periodic indexing error of the {} table (a worm wheel's tooth period)", kAxisLetters[a.index]),
      PeriodicScan{kRadPerDeg, 1.0, 90.0, "deg", "urad",
                   fmt::format("the table probed as {} turns", kAxisLetters[a.index])}));
}

// The rotary axis' line: its centre off (eccentricity) and its tilt (ISO 230-7's location
// errors).
void rotary_location(LibraryContext& ctx, const AxisInfo& a, std::span<const AxisInfo>, std::vector<Candidate>& out) {
  for (int component = 0; component < 6; ++component) {
    // Along or about its own line a rotary axis' location changes nothing.
    if (component == a.own || component == a.own - 3) continue;
    const std::string term = term_name(component, a.link, true);
    Candidate l;
    l.effect = component < 3 ? fmt::format("the {} axis' centre is off in {} (eccentricity, location)",
                                           kAxisLetters[a.index], kComponents[static_cast<std::size_t>(component)])
                             : fmt::format("the {} axis is tilted about {}", kAxisLetters[a.index],
                                           kComponents[static_cast<std::size_t>(component - 3)]);
    l.error = term, l.term = term, l.variable = axis_name(a.index), l.form = "polynomial";
    l.probe = ctx.probe(a.link, component, model::ErrorPlacement::location);
    l.basis = [](const Observation&, int, double) { return 1.0; };
    l.yaml = [term, component](const Eigen::VectorXd& x, double) {
      return fmt::format("{{name: {}, value: {:.4g}, unit: {}, fit: true}}", term, file_value(component, x[0]),
                         unit_of(component));
    };
    out.push_back(l);
  }
}

// The tool: a tilt of the spindle shows as an error growing with the tool length (Abbe).
void spindle_tilt(LibraryContext& ctx, std::vector<Candidate>& out) {
  if (ctx.spindle.empty() || !ctx.tool_length_varies) return;
  for (int component = 3; component < 5; ++component) {
    const std::string term = term_name(component, ctx.spindle, true);
    Candidate t;
    t.effect = fmt::format("the spindle is tilted about {}: the error grows with the tool length (Abbe arm)",
                           kComponents[static_cast<std::size_t>(component - 3)]);
    t.error = term, t.term = term, t.variable = "L", t.form = "linear";
    t.probe = ctx.probe(ctx.spindle, component);
    t.basis = [](const Observation&, int, double) { return 1.0; };
    t.yaml = [term, component](const Eigen::VectorXd& x, double) {
      return fmt::format("{{name: {}, value: {:.4g}, unit: urad, fit: true}}", term, file_value(component, x[0]));
    };
    out.push_back(t);
  }
}

// Heat: a drift of the tool against the workpiece with a sensor's temperature, or in time.
void spindle_heat(LibraryContext& ctx, std::vector<Candidate>& out) {
  if (ctx.spindle.empty()) return;
  for (int component = 0; component < 3; ++component) {
    const std::string term = term_name(component, ctx.spindle, false);
    for (std::size_t sensor = 0; sensor < ctx.data.sensors.size(); ++sensor) {
      if (!ctx.sensor_varies(sensor)) continue;
      Candidate d;
      d.effect = fmt::format("thermal drift in {} with the temperature at {}",
                             kComponents[static_cast<std::size_t>(component)], ctx.data.sensors[sensor]);
      d.error = "thermal", d.term = term, d.variable = "T_" + ctx.data.sensors[sensor], d.form = "linear";
      d.probe = ctx.probe(ctx.spindle, component);
      d.basis = [sensor](const Observation& o, int, double) { return o.temperatures[sensor] - 20.0; };
      d.yaml = [term, sensor_name = ctx.data.sensors[sensor], component](const Eigen::VectorXd& x, double) {
        return fmt::format(
            "{{name: {}, variable: T_{}, form: thermal, unit: um, coefficient: {:.4g}, fit: "
            "true}}",
            term, sensor_name, file_value(component, x[0]));
      };
      out.push_back(d);
    }
    if (ctx.time_varies) {
      Candidate w;
      w.effect = fmt::format("warm-up drift in {}: first order in time since the start",
                             kComponents[static_cast<std::size_t>(component)]);
      w.error = "thermal", w.term = term, w.variable = "t", w.form = "exponential";
      w.probe = ctx.probe(ctx.spindle, component);
      w.basis = [](const Observation& o, int, double tau) { return 1.0 - std::exp(-o.time / tau); };
      w.scan_from = 120.0, w.scan_to = 4 * 3600.0, w.scan_points = 60;
      w.scan_spacing = Candidate::Spacing::logarithmic;
      w.yaml = [term, component](const Eigen::VectorXd& x, double tau) {
        return fmt::format(
            "{{name: {}, variable: t, form: warmup, unit: um, amplitude: {:.4g}, time_constant: "
            "{:.0f} s, fit: true}}",
            term, file_value(component, x[0]), tau);
      };
      out.push_back(w);
    }
  }
}

}  // namespace ccomp::identify::detail
