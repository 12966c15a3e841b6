#pragma once
// Simulated measurements: a truth model measured by a plan, with noise. Users rehearse the
// fit-check loop with it; the identification tests are built on it.
#include <cstdint>
#include <string>
#include <vector>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

enum class Plan : std::uint8_t {
  nine_lines,  ///< Ref 4 (docs/error-model.md): three laser lines per linear axis, bidirectional passes
  grid,        ///< a volumetric grid of full deviations at several tool lengths
  sphere,      ///< spheres on the table probed at rotary angles (any rotary axes: sphere_poses)
  thermal,     ///< a drift test: fixed points over hours, sensors warming up
  test_piece,  ///< Ref 2 (docs/error-model.md): faces cut at B 0/90/180/270 deg, probed on a CMM along their normals
};

/// "nine_lines" -> Plan; throws ccomp::Error (usage) naming the known plans.
[[nodiscard]] Plan plan_from_name(const std::string& name);

struct SimulateOptions {
  std::vector<Plan> plans{Plan::nine_lines};
  double noise = 0.0002;  ///< mm, standard deviation of every reading
  unsigned seed = 1;
  double tool_length = 100.0;  ///< mm, the optic's or probe's length where a plan has one
  double step = 25.0;          ///< mm between points along a laser line
  double rotary_step = 15.0;   ///< deg between the sphere's probings
  int runs = 1;
  /// Where lines 1 and 3 of each axis sit, as a fraction of the workspace from its edges
  /// (0.1: near the edges, Ref 4's advice; 0.5 would put all three lines together).
  double line_inset = 0.1;  ///< out-and-back runs of each laser line (ISO 230-2 asks for 5)
  double hours = 4.0;       ///< length of the thermal run
  /// Sensor temperatures at the end of the thermal run (degC); 20 elsewhere.
  std::vector<double> warm_temperatures;
  /// Where program zero lies in machine coordinates (mm, deg): the plans on the part (the
  /// spheres, the test piece) are placed in program coordinates from it; the laser lines,
  /// the grid and the thermal points span the machine's axes wherever program zero is.
  model::WorkOrigin origin{};
};

/// A laser line's targets from `from` to `to` about every `step` (mm), as ISO 230-2 (sect.
/// 5.3.2) asks: P_i = (i - 1) p + r_i, p the interval that fits the travel, r_i an irregular
/// offset within +-p/4 (0 at the ends, which are the travel's), the same for every run, so
/// that a periodic error (a screw's pitch) is read at different phases and aliases no other.
[[nodiscard]] std::vector<double> iso230_targets(double from, double to, double step);

/// The sphere plan's axis positions (mm, rad, the tool length last) on a machine turning other
/// than a B table alone: two spheres on the part, at different radii and heights from program
/// zero, each probed at every combination of the rotary axes' angles (a full turn in
/// `rotary_step` where the axis turns one, else its range in about 30 degree steps), the linear
/// axes placed so the nominal tip is on the sphere's centre as the table turns it. Poses
/// beyond an axis' limits are left out.
[[nodiscard]] std::vector<model::ChainQ> sphere_poses(const model::ForwardModel& truth, const SimulateOptions& options);

/// Measures `truth` along the plans: each observation is the truth's prediction plus
/// Gaussian noise. The workspace is the axes' limits (a 400 mm cube where unlimited). Throws
/// ccomp::Error (safety) where the truth's error is not a number or beyond its max_correction:
/// no NaN row is ever written.
[[nodiscard]] MeasurementSet simulate(const model::ForwardModel& truth, const SimulateOptions& options);

}  // namespace ccomp::identify
