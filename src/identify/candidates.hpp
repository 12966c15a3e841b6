#pragma once
// Private to diagnose(): the library of candidate effects. Each is a term with a sentence
// of physics, the probe (a link and a component) it enters through, and its basis
// functions of a reading; the axes the data cover, which the library is built from.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::identify::detail {

inline constexpr std::string_view kComponents = "XYZABC";

/// Where a candidate term enters: a link and a component. Its column for an observation
/// is g (d prediction / d term value) times the candidate's basis function there.
struct Probe {
  std::string link;
  int component = 0;
  model::ErrorPlacement placement = model::ErrorPlacement::motion;
  Eigen::VectorXd g;               // per observation
  std::vector<Eigen::Index> rows;  // where g is not zero
  Eigen::VectorXd r_rows;          // the residual there (empty when they are all rows)
};

/// How many of its cycles the data must cover for a periodic effect to be named.
inline constexpr double kCyclesForAPeriod = 4.0;

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
  /// Periodic candidates whose readings sample the variable on a lattice: its step (mm,
  /// deg; 0 where the targets are irregular), the shortest period a mechanism of the kind
  /// has, and the run that would tell a period from its aliases.
  double lattice_step = 0.0, shortest_period = 0.0;
  std::string settling_run, period_unit;
  /// The YAML term with coefficients (internal units) and the scanned value.
  std::function<std::string(const Eigen::VectorXd&, double)> yaml;
};

/// An axis the model has, with its link and what the data cover of it.
struct AxisInfo {
  std::size_t index = 0;
  std::string link;
  bool rotary = false;
  int own = 0;              // the component along (or about) the axis
  double from = 0, to = 0;  // range in the data (mm, deg)
  double step = 0;          // the typical spacing of the data along it (mm, deg)
  bool on_lattice = false;  // the readings' positions along it lie every `step` (aliasing.hpp)
};

/// The lower-case letter of axis `i` (0 = x).
[[nodiscard]] std::string axis_name(std::size_t i);
/// An axis' position in a reading, in the file's units (mm, deg).
[[nodiscard]] double axis_value(const Observation& o, const AxisInfo& a);
/// The model's axes with what the data cover of each.
[[nodiscard]] std::vector<AxisInfo> axes_of(const model::MachineModel& mm, const MeasurementSet& data);
/// A term's ISO name: "EXX", a location error "EC0X".
[[nodiscard]] std::string term_name(int component, const std::string& link, bool location);

/// The candidate effects the data can show, with the probes (links and components) they
/// enter. The candidates refer to `axes`, which must outlive them.
[[nodiscard]] std::vector<Candidate> candidate_library(const model::MachineModel& mm, const MeasurementSet& data,
                                                       const std::vector<AxisInfo>& axes, std::vector<Probe>& probes);

/// A candidate's columns at a scanned value (a period, a time constant): its probe's
/// column times each basis function, on the probe's rows (`out` has a row per probe row),
/// or on every reading (`out` has n rows, zero off the probe's rows).
void candidate_columns(const Candidate& c, const Probe& p, const MeasurementSet& data, double value, bool every_row,
                       Eigen::Ref<Eigen::MatrixXd> out);

}  // namespace ccomp::identify::detail
