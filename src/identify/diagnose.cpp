#include "ccomp/identify/diagnose.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <optional>

#include "ccomp/identify/check.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/next_measurement.hpp"
#include "ccomp/identify/physical_scale.hpp"
#include "ccomp/util/parallel.hpp"

namespace ccomp::identify {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadPerDeg = kPi / 180.0;
/// A candidate is suggested when the chi-square falls by this much (five sigma) beyond
/// what noise and its scan would give.
constexpr double kSignificance = 25.0;
constexpr std::string_view kComponents = "XYZABC";
constexpr std::string_view kAxisLetters = "XYZABCUVW";

/// Where a candidate term enters: a link and a component. Its column for an observation
/// is g (d prediction / d term value) times the candidate's basis function there.
struct Probe {
  std::string link;
  int component = 0;
  model::ErrorPlacement placement = model::ErrorPlacement::motion;
  Eigen::VectorXd g;               // per observation
  std::vector<Eigen::Index> rows;  // where g is not zero
  Eigen::MatrixXd A_rows;          // the base's columns on those rows (empty when they are all rows)
  Eigen::VectorXd r_rows;          // the residual there
};

/// How many of its cycles the data must cover for a periodic effect to be named.
constexpr double kCyclesForAPeriod = 4.0;

/// A candidate effect: its words, its term, and its basis functions of an observation
/// (a scanned parameter, a period or a time constant, where it has one).
struct Candidate {
  std::string effect, error, term, variable, form;
  double period = 0.0;  // a harmonic's fixed period (deg)
  std::size_t probe = 0;
  int basis_count = 1;
  std::function<double(const Observation&, int k, double scanned)> basis;
  double scan_from = 0.0, scan_to = 0.0;  // of the scanned parameter (0, 0: none)
  /// How the scanned parameter is stepped: evenly in 1/value (periods), in log value (time
  /// constants), or in value (a place along an axis).
  enum class Spacing : std::uint8_t { frequency, logarithmic, linear } scan_spacing = Spacing::frequency;
  int scan_points = 0;
  /// Periodic candidates: the variable the period is in (mm, deg); the coarse scan steps
  /// the phase of every row by rotation instead of calling the basis. Local candidates: the
  /// variable the scanned place is in.
  std::function<double(const Observation&)> phase_variable;
  /// Local candidates: how far from the scanned place a row still counts (its basis is
  /// below 4e-6 beyond: 5 standard deviations of a bell).
  double reach = 0.0;
  /// The YAML term with coefficients (internal units) and the scanned value.
  std::function<std::string(const Eigen::VectorXd&, double)> yaml;
};

/// Makes `c` a sinusoid of a scanned period in `variable` (mm, deg): cos and sin.
void periodic_in(Candidate& c, std::function<double(const Observation&)> variable) {
  c.basis_count = 2;
  c.basis = [variable](const Observation& o, int k, double period) {
    const double phase = 2 * kPi * variable(o) / period;
    return k == 0 ? std::cos(phase) : std::sin(phase);
  };
  c.phase_variable = std::move(variable);
}

/// A sinusoid's gain (the fall in the sum of squares when its cos and sin columns g cos,
/// g sin join, leaving out what the base absorbs) at `count` evenly spaced frequencies
/// f0 + k df of `variable`, for the residual r. Each row's (cos, sin) turns by one
/// rotation per frequency. Rows are taken a block at a time through all frequencies: the
/// block stays in the first-level cache, the rows are read from memory once.
std::vector<double> coarse_periodic_gains(const std::vector<double>& variable, const std::vector<double>& g,
                                          const Eigen::VectorXd& r, double f0, double df, std::size_t count) {
  const auto rows = static_cast<Eigen::Index>(variable.size());
  Eigen::ArrayXd cs(rows), sn(rows), step_c(rows), step_s(rows), gr(rows), g2(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    const double v = variable[static_cast<std::size_t>(i)], gi = g[static_cast<std::size_t>(i)];
    cs[i] = std::cos(2 * kPi * v * f0), sn[i] = std::sin(2 * kPi * v * f0);
    step_c[i] = std::cos(2 * kPi * v * df), step_s[i] = std::sin(2 * kPi * v * df);
    gr[i] = gi * r[i];
    g2[i] = gi * gi;
  }
  // Per frequency: g r cos, g r sin, g^2 cos^2, g^2 cos sin, g^2 sin^2, summed.
  std::vector<std::array<double, 5>> sums(count, std::array<double, 5>{});
  constexpr Eigen::Index kBlock = 256;
  Eigen::ArrayXd turned(kBlock);
  for (Eigen::Index begin = 0; begin < rows; begin += kBlock) {
    const Eigen::Index size = std::min(kBlock, rows - begin);
    auto c = cs.segment(begin, size), s = sn.segment(begin, size);
    const auto sc = step_c.segment(begin, size), ss = step_s.segment(begin, size);
    const auto w = gr.segment(begin, size), w2 = g2.segment(begin, size);
    auto t = turned.head(size);
    for (std::size_t k = 0; k < count; ++k) {
      std::array<double, 5>& sum = sums[k];
      sum[0] += (w * c).sum(), sum[1] += (w * s).sum();
      sum[2] += (w2 * c.square()).sum(), sum[3] += (w2 * c * s).sum(), sum[4] += (w2 * s.square()).sum();
      t = c * sc - s * ss;
      s = s * sc + c * ss;
      c = t;
    }
  }
  std::vector<double> gains(count);
  for (std::size_t k = 0; k < count; ++k) {
    const auto& [b0, b1, n00, n01, n11] = sums[k];
    const double det = n00 * n11 - n01 * n01;
    gains[k] = det > 1e-12 * n00 * n11 ? (n11 * b0 * b0 - 2 * n01 * b0 * b1 + n00 * b1 * b1) / det : 0.0;
  }
  return gains;
}

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

/// A scored candidate: its suggestion, and the value and coefficients it was scored at.
struct Scored {
  Suggestion suggestion;
  double value = 0.0;
  Eigen::VectorXd coefficients;
};

/// The refitted model's residual and what its free parameters can absorb.
struct Projector {
  Eigen::VectorXd r;  // residual, orthogonal to the base columns
  Eigen::MatrixXd A;  // the base's columns (the refit's design matrix), scaled to unit length: n x m
  Eigen::MatrixXd W;  // m x k: A W is an orthonormal basis of the combinations the data identify

  /// The fall in the sum of squares when columns C join the base fit, and their
  /// coefficients. C is given on some rows (a probe's), `r_rows` is the residual there
  /// and `AtC` is A^T C over the same rows (m x C.cols()). U = A W is never formed: what
  /// the base absorbs of C is W^T (A^T C), and A^T C is one product for many candidates.
  double gain(const Eigen::Ref<const Eigen::MatrixXd>& C, const Eigen::Ref<const Eigen::VectorXd>& r_rows,
              const Eigen::Ref<const Eigen::MatrixXd>& AtC, Eigen::VectorXd* coefficients) const {
    const Eigen::Index k = C.cols();
    const Eigen::VectorXd b = C.transpose() * r_rows;
    const Eigen::MatrixXd CtC = C.transpose() * C;
    const Eigen::MatrixXd UtC = W.transpose() * AtC;
    const Eigen::MatrixXd N = CtC - UtC.transpose() * UtC;
    // Columns scaled to unit diagonal; a column the base already spans gains nothing.
    Eigen::VectorXd d = N.diagonal().cwiseMax(0.0).cwiseSqrt();
    for (Eigen::Index j = 0; j < k; ++j)
      if (!(d[j] > 1e-9 * std::sqrt(std::max(CtC(j, j), 1e-300)))) return 0.0;
    const Eigen::MatrixXd Ns = d.cwiseInverse().asDiagonal() * N * d.cwiseInverse().asDiagonal();
    const Eigen::VectorXd bs = b.cwiseQuotient(d);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Ns);
    // Columns that are nearly one another once the base is out: the candidate is not one effect.
    if (eig.eigenvalues().minCoeff() < 1e-6) return 0.0;
    const Eigen::VectorXd xs =
        eig.eigenvectors() * (eig.eigenvectors().transpose() * bs).cwiseQuotient(eig.eigenvalues());
    if (coefficients) *coefficients = xs.cwiseQuotient(d);
    return bs.dot(xs);
  }
};

std::string axis_name(std::size_t i) {
  return std::string(1, static_cast<char>(std::tolower(kAxisLetters[i])));
}

/// An axis the model has, with its link and what the data cover of it.
struct AxisInfo {
  std::size_t index = 0;
  std::string link;
  bool rotary = false;
  int own = 0;              // the component along (or about) the axis
  double from = 0, to = 0;  // range in the data (mm, deg)
  double step = 0;          // the typical spacing of the data along it (mm, deg)
};

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
      a.from = 1e300, a.to = -1e300;
      const auto qi = static_cast<Eigen::Index>(a.index);
      for (const Observation& o : data.observations) {
        const double v = axis_value(o, a);
        a.from = std::min(a.from, v), a.to = std::max(a.to, v);
      }
      // The median spacing between consecutive readings that differ along this axis only.
      std::vector<double> steps;
      for (std::size_t i = 1; i < data.observations.size(); ++i) {
        const model::ChainQ d = data.observations[i].q - data.observations[i - 1].q;
        const double travel = std::abs(d[qi]);
        if (travel > 1e-9 && d.norm() - travel < 1e-9 * (1.0 + travel))
          steps.push_back(a.rotary ? travel / kRadPerDeg : travel);
      }
      if (!steps.empty()) {
        std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
        a.step = steps[steps.size() / 2];
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
    probes.push_back(Probe{link, component, placement, {}, {}, {}, {}});
    return probes.size() - 1;
  };
  const auto location = model::ErrorPlacement::location;
  auto position = [](const Observation& o, const AxisInfo& a) {  // internal units: mm, rad
    return o.q[static_cast<Eigen::Index>(a.index)];
  };
  auto varies = [&](auto get) {
    double lo = 1e300, hi = -1e300;
    for (const Observation& o : data.observations) lo = std::min(lo, get(o)), hi = std::max(hi, get(o));
    return hi > lo + 1e-12;
  };
  const bool tool_length_varies = varies([](const Observation& o) { return o.q[9]; });
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
      // Periods below 2.5 steps of the data along the axis would alias.
      // A period is named only where the data cover enough of its cycles to tell it from a
      // slow curve (a shape the library lacks, a thermal drift seen along a line): four.
      c.scan_from = std::max(2.0, 2.5 * a.step), c.scan_to = span / kCyclesForAPeriod;
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
      // Reversal: the axis' positioning differs with the approach direction (backlash).
      const std::size_t vi = a.index;
      if (varies([vi](const Observation& o) { return o.directions[vi]; })) {
        Candidate r;
        r.effect = fmt::format(
            "reversal of the {} axis: its position depends on the approach direction (backlash, "
            "lost motion)",
            kAxisLetters[a.index]);
        r.error = own, r.term = own, r.variable = "v" + v, r.form = "reversal";
        r.probe = probe(a.link, a.own);
        r.basis = [vi](const Observation& o, int, double) { return 0.5 * o.directions[vi]; };
        r.yaml = [own, v, file_value, component = a.own](const Eigen::VectorXd& x, double) {
          return fmt::format("{{name: {}, variable: v{}, form: reversal, unit: um, reversal: {:.4g}, fit: true}}", own,
                             v, file_value(component, x[0]));
        };
        candidates.push_back(r);
      }
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
      w.scan_from = std::max(1.0, 2.5 * a.step), w.scan_to = std::min(90.0, span / kCyclesForAPeriod);
      w.scan_points = static_cast<int>(std::clamp(2.0 * span / w.scan_from, 50.0, 6000.0));
      w.yaml = [own, file_value, component = a.own](const Eigen::VectorXd& x, double period) {
        return fmt::format(
            "{{name: {}, form: periodic, period: {:.6g} deg, unit: urad, harmonics: [[{:.4g}, "
            "{:.4g}]], fit: true}}",
            own, period, file_value(component, x[0]), file_value(component, x[1]));
      };
      candidates.push_back(w);
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

/// The base model refitted to the data and what its free parameters can absorb, with the
/// probes' columns: one pass over the data, with a model that has the probes as terms
/// (zero: its predictions are the refit's), gives the base's columns and the probes' alike.
Projector refitted_base(const model::ForwardModel& model, const MeasurementSet& data, std::vector<Probe>& probes,
                        const FitOptions& fit_options, Diagnosis& out) {
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  out.refit = fit(model, data, fit_options);
  model::MachineModel probing = model.machine();
  const std::size_t first = probing.terms.size();
  for (const Probe& p : probes) {
    model::ErrorTermSpec t;
    t.name = t.iso = term_name(p.component, p.link, true);
    t.link = p.link;
    t.component = p.component;
    t.placement = p.placement;
    t.parameters = Eigen::VectorXd::Zero(1);
    t.parameter_unit = {1.0};
    probing.terms.push_back(t);
  }
  const model::ForwardModel f(probing);
  std::vector<std::size_t> columns = free_parameters(model);  // the base's terms keep their offsets in f
  const auto m = static_cast<Eigen::Index>(columns.size());
  for (std::size_t k = 0; k < probes.size(); ++k) columns.push_back(f.parameter_offset(first + k));
  Eigen::VectorXd parameters = model_parameters(f);
  parameters.head(out.refit.all_parameters.size()) = out.refit.all_parameters;
  Projector base;
  {
    Eigen::MatrixXd J;
    design_matrix(f, parameters, data, columns, base.r, &J);
    for (std::size_t k = 0; k < probes.size(); ++k) probes[k].g = J.col(m + static_cast<Eigen::Index>(k));
    base.A = J.leftCols(m);
  }
  if (base.A.cols() > 0) {
    // What the base absorbs is what its fit could determine: columns in physical scales,
    // directions whose effect at that size is above the noise (fit.hpp).
    const Eigen::VectorXd physical = physical_scales(model, data);
    for (Eigen::Index j = 0; j < base.A.cols(); ++j)
      base.A.col(j) *= physical[static_cast<Eigen::Index>(columns[static_cast<std::size_t>(j)])];
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(normal_matrix(base.A));
    const double largest = std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0));
    const double seen = std::max(3.0 * out.refit.noise, 1e-9 * largest);
    std::vector<Eigen::Index> kept;
    for (Eigen::Index k = 0; k < eig.eigenvalues().size(); ++k)
      if (std::sqrt(std::max(eig.eigenvalues()[k], 0.0)) > seen) kept.push_back(k);
    base.W.resize(base.A.cols(), static_cast<Eigen::Index>(kept.size()));
    for (std::size_t c = 0; c < kept.size(); ++c)
      base.W.col(static_cast<Eigen::Index>(c)) =
          eig.eigenvectors().col(kept[c]) / std::sqrt(eig.eigenvalues()[kept[c]]);
    // The refit's residual, made exactly orthogonal to what the base absorbs.
    const Eigen::VectorXd absorbed = base.W * (base.W.transpose() * (base.A.transpose() * base.r));
    base.r -= base.A * absorbed;
  } else {
    base.W.resize(0, 0);
  }
  out.rms_refit = std::sqrt(base.r.squaredNorm() / static_cast<double>(n));
  return base;
}

/// Each probe's rows (where its column is not zero), and the base on them.
void probe_rows(const Projector& base, Eigen::Index n, std::vector<Probe>& probes) {
  for (Probe& p : probes) {
    const double largest = p.g.cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i < n; ++i)
      if (std::abs(p.g[i]) > 1e-9 * largest) p.rows.push_back(i);
    if (static_cast<Eigen::Index>(p.rows.size()) == n) continue;  // every row: the base's own A and r serve
    p.A_rows.resize(static_cast<Eigen::Index>(p.rows.size()), base.A.cols());
    p.r_rows.resize(static_cast<Eigen::Index>(p.rows.size()));
    for (std::size_t i = 0; i < p.rows.size(); ++i) {
      if (base.A.cols() > 0) p.A_rows.row(static_cast<Eigen::Index>(i)) = base.A.row(p.rows[i]);
      p.r_rows[static_cast<Eigen::Index>(i)] = base.r[p.rows[i]];
    }
  }
}

/// Where the residual concentrates: eight bins along every variable that varies.
std::vector<Region> residual_regions(const model::MachineModel& mm, const MeasurementSet& data,
                                     const std::vector<AxisInfo>& axes, const Eigen::VectorXd& r, double overall,
                                     double noise) {
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  std::vector<Region> regions;
  auto add_regions = [&](const std::string& variable, auto get) {
    double lo = 1e300, hi = -1e300;
    for (const Observation& o : data.observations)
      if (const double v = get(o); !std::isnan(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (!(hi > lo)) return;
    constexpr int kBins = 8;
    std::vector<double> sum(kBins, 0.0), count(kBins, 0.0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Observation& o = data.observations[static_cast<std::size_t>(i)];
      if (std::isnan(get(o))) continue;  // a sensor this reading's file does not have
      const int bin = std::min(kBins - 1, static_cast<int>((get(o) - lo) / (hi - lo) * kBins));
      sum[static_cast<std::size_t>(bin)] += r[i] * r[i];
      count[static_cast<std::size_t>(bin)] += 1;
    }
    for (int b = 0; b < kBins; ++b) {
      const auto bi = static_cast<std::size_t>(b);
      if (count[bi] < 10) continue;
      const double rms = std::sqrt(sum[bi] / count[bi]);
      if (overall > 0 && rms > 1.5 * overall && rms > 3 * noise)
        regions.push_back({variable, lo + (hi - lo) * b / kBins, lo + (hi - lo) * (b + 1) / kBins, rms, rms / overall});
    }
  };
  for (const AxisInfo& a : axes)
    add_regions(axis_name(a.index), [&a](const Observation& o) { return axis_value(o, a); });
  add_regions("L", [](const Observation& o) { return o.q[9]; });
  add_regions("t", [](const Observation& o) { return o.time; });
  for (std::size_t s = 0; s < data.sensors.size(); ++s)
    add_regions("T_" + data.sensors[s],
                [s](const Observation& o) { return s < o.temperatures.size() ? o.temperatures[s] : std::nan(""); });
  std::sort(regions.begin(), regions.end(), [](const Region& a, const Region& b) { return a.ratio > b.ratio; });
  if (regions.size() > 8) regions.resize(8);
  return regions;
}

}  // namespace

Diagnosis diagnose(const model::ForwardModel& model, const MeasurementSet& data, const DiagnoseOptions& options) {
  const model::MachineModel& mm = model.machine();
  Diagnosis out;
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  if (n == 0) return out;
  // Too few readings to refit the model: no diagnosis, said (the model as it is against the
  // data is still worth reading; `fit` refuses such data).
  if (const std::size_t free = free_parameters(model).size(); data.observations.size() < free) {
    out.skipped = fmt::format(
        "{} readings cannot determine the model's {} free parameters: no refit, no "
        "diagnosis (measure more, or free fewer terms)",
        data.observations.size(), free);
    return out;
  }
  out.noise = options.noise > 0 ? options.noise : check(model, data).noise_floor;

  const std::vector<AxisInfo> axes = axes_of(mm, data);
  std::vector<Probe> probes;
  const std::vector<Candidate> candidates = candidate_library(mm, data, axes, probes);
  out.candidates_tried = candidates.size();
  Projector base = refitted_base(model, data, probes, options.fit, out);
  probe_rows(base, n, probes);
  const double sse0 = base.r.squaredNorm();
  // Without a noise floor from the data's structure, the refitted residual stands in for
  // it: an upper bound, so fewer effects pass, never more.
  if (!(out.noise > 0)) out.noise = out.rms_refit;
  const double sigma2 = std::max(out.noise * out.noise, 1e-18);

  // A candidate's suggestion from its best value (a period, a time constant), the gain
  // there and its coefficients.
  auto suggestion = [&](const Candidate& c, double value, double gain, const Eigen::VectorXd& x, double uncertainty,
                        double trials) -> std::optional<Scored> {
    if (!(gain > 0)) return std::nullopt;
    Suggestion s;
    s.effect = c.effect, s.error = c.error, s.term = c.term, s.variable = c.variable, s.form = c.form;
    s.period = c.scan_points > 0 || c.form == "harmonic" ? value : 0.0;
    s.period_uncertainty = uncertainty;
    s.rms_before = out.rms_refit;
    const double sse1 = std::max(sse0 - gain, 0.0);
    s.rms_after = std::sqrt(sse1 / static_cast<double>(n));
    const auto k = static_cast<double>(c.basis_count + (c.scan_points > 0 ? 1 : 0));
    s.bic_delta = static_cast<double>(n) * std::log(std::max(sse1, 1e-300) / std::max(sse0, 1e-300)) +
                  k * std::log(static_cast<double>(n));
    // Against the noise floor: the fall in chi-square, less what the parameters and the
    // scan would win from noise alone (2 ln(trials) for the look-elsewhere effect).
    s.significance = gain / sigma2 - k - 2.0 * std::log(trials);
    s.yaml = "  - " + c.yaml(x, value);
    s.spec = c.yaml(x, value);
    return Scored{std::move(s), value, x};
  };

  // Candidates without a scan: all their columns (over every row, zero off their probe's
  // rows) in one matrix, and what the base absorbs of them in one product over the data,
  // instead of a pass over the base's columns per candidate.
  std::vector<Eigen::Index> fixed_column(candidates.size(), -1);
  Eigen::Index fixed_columns = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].scan_points == 0 && !probes[candidates[i].probe].rows.empty())
      fixed_column[i] = fixed_columns, fixed_columns += candidates[i].basis_count;
  Eigen::MatrixXd C_fixed = Eigen::MatrixXd::Zero(n, fixed_columns);
  util::for_each_index(candidates.size(), options.threads, [&](std::size_t i) {
    if (fixed_column[i] < 0) return;
    const Candidate& c = candidates[i];
    candidate_columns(c, probes[c.probe], data, c.period, true, C_fixed.middleCols(fixed_column[i], c.basis_count));
  });
  const Eigen::MatrixXd AtC_fixed = transpose_product(base.A, C_fixed);
  auto score_fixed = [&](std::size_t i) {
    const Candidate& c = candidates[i];
    Eigen::VectorXd x;
    const double gain = base.gain(C_fixed.middleCols(fixed_column[i], c.basis_count), base.r,
                                  AtC_fixed.middleCols(fixed_column[i], c.basis_count), &x);
    return suggestion(c, c.period, gain, x, 0.0, 1.0);
  };

  // Candidates with a scan (a period, a time constant): a coarse pass, then the best
  // values weighed exactly, a few at a time in one product.
  auto score_scanned = [&](const Candidate& c) -> std::optional<Scored> {
    const Probe& p = probes[c.probe];
    if (p.rows.empty()) return std::nullopt;
    const bool all_rows = static_cast<Eigen::Index>(p.rows.size()) == n;
    const Eigen::MatrixXd& A_rows = all_rows ? base.A : p.A_rows;
    const Eigen::VectorXd& r_rows = all_rows ? base.r : p.r_rows;
    // The exact gains at `values`; the coefficients at the first of them into `x`.
    auto exact_gains = [&](const std::vector<double>& values, Eigen::VectorXd* x) {
      const int bc = c.basis_count;
      Eigen::MatrixXd C(static_cast<Eigen::Index>(p.rows.size()), static_cast<Eigen::Index>(values.size()) * bc);
      for (std::size_t v = 0; v < values.size(); ++v)
        candidate_columns(c, p, data, values[v], false, C.middleCols(static_cast<Eigen::Index>(v) * bc, bc));
      const Eigen::MatrixXd AtC = A_rows.transpose() * C;
      std::vector<double> gains(values.size());
      for (std::size_t v = 0; v < values.size(); ++v) {
        const Eigen::Index first = static_cast<Eigen::Index>(v) * bc;
        gains[v] = base.gain(C.middleCols(first, bc), r_rows, AtC.middleCols(first, bc), v == 0 ? x : nullptr);
      }
      return gains;
    };
    // The coarse gains' eight best local peaks weighed exactly; only they compete (the
    // coarse gains elsewhere are not comparable).
    auto keep_exact_peaks = [&](const std::vector<double>& values, std::vector<double>& gains) {
      std::vector<std::pair<double, std::size_t>> peaks;
      for (std::size_t k = 0; k < gains.size(); ++k)
        if ((k == 0 || gains[k] >= gains[k - 1]) && (k + 1 == gains.size() || gains[k] >= gains[k + 1]))
          peaks.emplace_back(-gains[k], k);
      std::sort(peaks.begin(), peaks.end());
      if (peaks.size() > 8) peaks.resize(8);
      std::vector<double> peak_values;
      for (const auto& peak : peaks) peak_values.push_back(values[peak.second]);
      const std::vector<double> exact = exact_gains(peak_values, nullptr);
      for (std::size_t i = 0; i < peaks.size(); ++i) gains[peaks[i].second] = exact[i];
      for (std::size_t k = 0; k < gains.size(); ++k)
        if (std::none_of(peaks.begin(), peaks.end(), [k](const auto& peak) { return peak.second == k; }))
          gains[k] = -1.0;
    };
    // Evenly in frequency for periods (each step shifts the phase at the far end by the
    // same amount), in log for time constants, in value for places.
    std::vector<double> values(static_cast<std::size_t>(c.scan_points)), gains(values.size());
    for (std::size_t k = 0; k < values.size(); ++k) {
      const double f = static_cast<double>(k) / static_cast<double>(values.size() - 1);
      switch (c.scan_spacing) {
        case Candidate::Spacing::frequency:
          values[k] = 1.0 / (1.0 / c.scan_from + f * (1.0 / c.scan_to - 1.0 / c.scan_from));
          break;
        case Candidate::Spacing::logarithmic:
          values[k] = c.scan_from * std::pow(c.scan_to / c.scan_from, f);
          break;
        case Candidate::Spacing::linear:
          values[k] = c.scan_from + f * (c.scan_to - c.scan_from);
          break;
      }
    }
    if (c.scan_spacing == Candidate::Spacing::frequency && c.phase_variable) {
      // A long frequency scan's coarse pass leaves out what the base absorbs (cheap);
      // its eight best local peaks are then weighed exactly. The frequencies are evenly
      // spaced, so each row's (cos, sin) steps by one rotation per frequency.
      std::vector<double> phase_variable(p.rows.size()), g(p.rows.size());
      for (std::size_t i = 0; i < p.rows.size(); ++i) {
        phase_variable[i] = c.phase_variable(data.observations[static_cast<std::size_t>(p.rows[i])]);
        g[i] = p.g[p.rows[i]];
      }
      gains = coarse_periodic_gains(phase_variable, g, r_rows, 1.0 / values[0], 1.0 / values[1] - 1.0 / values[0],
                                    values.size());
      keep_exact_peaks(values, gains);
    } else if (c.scan_spacing == Candidate::Spacing::linear) {
      // A place along an axis (a local defect): the coarse pass weighs each place by its
      // column's correlation with the residual alone (a bell is local: what the base
      // absorbs of it is small), and its eight best local peaks are then weighed exactly.
      // The rows by their place, so that each scanned place reads only the rows it reaches.
      std::vector<std::pair<double, Eigen::Index>> by_place;
      for (const Eigen::Index row : p.rows)
        by_place.emplace_back(c.phase_variable(data.observations[static_cast<std::size_t>(row)]), row);
      std::sort(by_place.begin(), by_place.end());
      for (std::size_t k = 0; k < values.size(); ++k) {
        double cr = 0.0, cc = 0.0;
        auto it = std::lower_bound(by_place.begin(), by_place.end(), std::pair{values[k] - c.reach, Eigen::Index{-1}});
        for (; it != by_place.end() && it->first <= values[k] + c.reach; ++it) {
          const Eigen::Index row = it->second;
          const double column = p.g[row] * c.basis(data.observations[static_cast<std::size_t>(row)], 0, values[k]);
          cr += column * base.r[row];
          cc += column * column;
        }
        gains[k] = cc > 0 ? cr * cr / cc : 0.0;
      }
      keep_exact_peaks(values, gains);
    } else {
      gains = exact_gains(values, nullptr);
    }
    const auto top = static_cast<std::size_t>(std::max_element(gains.begin(), gains.end()) - gains.begin());
    // Refining moves the peak by less than half a step, which raises its gain by a
    // quarter at most: a candidate that could not pass with twice its gain is not
    // refined (it is not suggested either way).
    const double trials = static_cast<double>(values.size());
    const auto parameters = static_cast<double>(c.basis_count + 1);
    if (2.0 * gains[top] / sigma2 - parameters - 2.0 * std::log(trials) <= kSignificance) return std::nullopt;
    // Refine between the neighbours on a grid, three times narrower each round, and put
    // the peak on the parabola through the best point and its neighbours.
    double lo = values[top > 0 ? top - 1 : top], hi = values[top + 1 < values.size() ? top + 1 : top];
    if (lo > hi) std::swap(lo, hi);
    constexpr int kGrid = 12;
    std::vector<double> grid(kGrid), grid_gains;
    std::size_t best = 0;
    for (int round = 0; round < 3; ++round) {
      for (int j = 0; j < kGrid; ++j) grid[static_cast<std::size_t>(j)] = lo + (hi - lo) * j / (kGrid - 1);
      grid_gains = exact_gains(grid, nullptr);
      best = static_cast<std::size_t>(std::max_element(grid_gains.begin(), grid_gains.end()) - grid_gains.begin());
      lo = grid[best > 0 ? best - 1 : best], hi = grid[std::min<std::size_t>(best + 1, kGrid - 1)];
    }
    double value = grid[best];
    if (best > 0 && best + 1 < kGrid) {
      const double bend = grid_gains[best - 1] - 2 * grid_gains[best] + grid_gains[best + 1];
      if (bend < 0) value += 0.5 * (grid[1] - grid[0]) * (grid_gains[best - 1] - grid_gains[best + 1]) / bend;
    }
    // The gain and coefficients there, and the uncertainty from the curvature of the sum
    // of squares (a chi-square rise of 1).
    // A place along an axis is as precise at 0 as anywhere: its step is the scan's range's.
    const double h = c.scan_spacing == Candidate::Spacing::linear || value == 0.0
                         ? 1e-4 * std::abs(c.scan_to - c.scan_from)
                         : 1e-4 * std::abs(value);
    Eigen::VectorXd x;
    const std::vector<double> last = exact_gains({value, value + h, value - h}, &x);
    const double curvature = (2 * last[0] - last[1] - last[2]) / (h * h);
    const double uncertainty = curvature > 0 ? std::sqrt(2.0 * sigma2 / curvature) : 0.0;
    return suggestion(c, value, last[0], x, uncertainty, trials);
  };

  // Scanned candidates first: they are the long ones, and the threads take indices in order.
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].scan_points > 0) order.push_back(i);
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (fixed_column[i] >= 0) order.push_back(i);
  std::vector<std::optional<Scored>> results(candidates.size());
  util::for_each_index(order.size(), options.threads, [&](std::size_t j) {
    const std::size_t i = order[j];
    results[i] = fixed_column[i] >= 0 ? score_fixed(i) : score_scanned(candidates[i]);
  });
  // Significant: the chi-square falls by 25 (five sigma) beyond what noise and the scan
  // would give, the information criterion agrees, and the rms falls by 3% at least.
  std::vector<std::size_t> kept;  // candidates
  for (std::size_t i = 0; i < results.size(); ++i)
    if (const Suggestion* s = results[i] ? &results[i]->suggestion : nullptr;
        s && s->significance > kSignificance && s->bic_delta < -10.0 && s->rms_after < 0.97 * s->rms_before)
      kept.push_back(i);
  std::stable_sort(kept.begin(), kept.end(), [&](std::size_t a, std::size_t b) {
    return results[a]->suggestion.bic_delta < results[b]->suggestion.bic_delta;
  });
  if (kept.size() > static_cast<std::size_t>(options.max_suggestions))
    kept.resize(static_cast<std::size_t>(options.max_suggestions));
  for (std::size_t rank = 0; rank < kept.size(); ++rank) {
    const Candidate& c = candidates[kept[rank]];
    Scored& scored = *results[kept[rank]];
    Suggestion& s = scored.suggestion;
    s.rank = static_cast<int>(rank + 1);
    // The residual with the effect added: what its terms take, less what the base's free
    // parameters had taken of it (the linear fit of both, whose rms is rms_after).
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, c.basis_count);
    candidate_columns(c, probes[c.probe], data, scored.value, true, C);
    Eigen::VectorXd taken = C * scored.coefficients;
    if (base.A.cols() > 0) taken -= base.A * (base.W * (base.W.transpose() * (base.A.transpose() * taken)));
    s.residual = base.r - taken;
    out.suggestions.push_back(std::move(s));
  }

  out.regions = residual_regions(mm, data, axes, base.r, out.rms_refit, out.noise);
  out.ties = find_ties(out.suggestions, base.r);
  out.residual = std::move(base.r);
  return out;
}

}  // namespace ccomp::identify
