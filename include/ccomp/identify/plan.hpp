#pragma once
// The next measurement for the programs at hand (`ccomp plan`): of groups of readings an
// instrument takes together (a grid of full deviations at a table angle, a laser line out
// and back along an axis), those that most reduce the model's uncertainty on the programs'
// poses, within a budget of readings. Greedy A-optimal design: each step takes the group
// whose readings remove the most of the programs' error variance per reading, given the
// data so far and the groups already taken (docs/identification.md, "Which measurement for
// this program").
#include <string>
#include <vector>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

/// A point a program's tool runs through: chain values and the conditions there.
struct ProgramPose {
  model::ChainQ q = model::ChainQ::Zero();
  model::Conditions conditions;
};

struct PlanOptions {
  std::size_t budget = 300;  ///< readings at most
  /// mm: one reading's noise (0: the data's floor, else 0.2 um; `plan` gives the model's
  /// fit information's where it has one).
  double noise = 0.0;
  /// The programs' poses used, spread over them (every k-th): enough for the variance's shape.
  std::size_t max_poses = 400;
};

struct PlannedGroup {
  std::string source;  ///< "plan-grid-B180", "plan-X-line-B90": what the readings are labelled
  std::string kind;    ///< "grid", "laser line"
  std::vector<Observation> readings;  ///< value 0: to be measured
  /// The programs' uncertainty (rms over their poses of the error's standard deviation, mm)
  /// before and after this group was taken.
  double before = 0.0, after = 0.0;
  std::string why;  ///< in words: what it pins down, where the data were thin
};

struct MeasurementPlan {
  std::vector<PlannedGroup> groups;
  std::vector<std::string> sources;  ///< the groups' sources, as Observation::source indexes them
  double before = 0.0, after = 0.0;  ///< mm, as PlannedGroup's, for the whole plan
  std::size_t readings = 0;
  std::size_t candidates = 0;  ///< groups considered
};

/// Plans the readings for `poses` (the programs'), given `data` measured so far on `model`
/// (its free terms are what is uncertain). Throws Error (data) when there are no poses.
[[nodiscard]] MeasurementPlan plan_measurements(const model::ForwardModel& model, const MeasurementSet& data,
                                                const std::vector<ProgramPose>& poses,
                                                const PlanOptions& options = {});

/// The plan as a file of the measurement contract without `d` (and without t or T_: the
/// instrument's run gives those), in `frame`, the groups one after the other.
[[nodiscard]] std::string plan_csv(const MeasurementPlan& plan, const model::MachineModel& model,
                                   const ResolvedFrame& frame);

/// A plan file (plan_csv(), or the same edited: the contract without `d`) read as
/// observations to be measured (values 0), in the frame its `# frame:` line or `options` say.
/// Throws Error (data) as the measurement reader does, at the file's row and column.
void read_plan(const std::string& path, const model::MachineModel& model, const ReadOptions& options,
               MeasurementSet& into);

/// Each observation of `set` measured on `truth`: its prediction plus Gaussian noise of
/// `noise` mm (`ccomp simulate --plan PLAN.csv`, a rehearsal of the plan).
void measure_on(const model::ForwardModel& truth, MeasurementSet& set, double noise, unsigned seed);

}  // namespace ccomp::identify
