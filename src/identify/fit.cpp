#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/fit_caveats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>

#include "ccomp/error.hpp"
#include "ccomp/model/term_forms.hpp"
#include "ccomp/util/parallel.hpp"
#include "fit_stages.hpp"

namespace ccomp::identify {

using model::TermForm;

std::string parameter_label(const model::ErrorTermSpec& t, std::size_t k) {
  return model::term_form(t.shape.form).parameter_label(t, k);
}

namespace {

/// Whether a term is the straightness of a linear axis as a polynomial of its position
/// (EYX of x) whose slope is where the axis' line lies, carried by a squareness the model
/// has free: its own line's (EC0X: X's line turned toward y gives the same column), or,
/// where the reference frame fixes this line (Z's line is its primary axis, Y's lies in its
/// Z-Y plane), the other line's that makes the same angle (EXZ's by EB0X, EYZ's by EA0Y,
/// EXY's by EC0X). Without that squareness free the slope stays the straightness'.
bool slope_is_a_location(const model::MachineModel& mm, const model::ErrorTermSpec& t) {
  if (t.shape.form != TermForm::polynomial || t.placement != model::ErrorPlacement::motion || t.component >= 3 ||
      t.primary.kind != model::VariableKind::axis)
    return false;
  for (const auto* chain : {&mm.workpiece_chain, &mm.tool_chain})
    for (const model::LinkSpec& l : *chain) {
      if (l.name != t.link || !l.axis || l.tool) continue;
      const model::AxisSpec* a = mm.axis(*l.axis);
      const std::size_t letter = index_of_letter(*l.axis);
      const int along = static_cast<int>(letter % 3);  // U V W travel along X Y Z
      if ((a && a->type == model::AxisType::rotary) || letter != t.primary.index || along == t.component) return false;
      const int about = 3 + (3 - along - t.component);  // the line turned toward the straightness' direction
      // Where the reference frame fixes this line's turn (Z's line is its primary axis, Y's
      // lies in its Z-Y plane), the angle between the two lines is the other line's
      // squareness: Z toward x is EB0X, Z toward y is EA0Y, Y toward x is EC0X.
      std::string carrier = t.link;
      int carried = about;
      const bool frame_fixed = model::frame_fixes_line_turn(*l.axis, about);
      if (frame_fixed) {
        const char other = (*l.axis == 'Z' && about == 3) ? 'Y' : 'X';
        carrier.clear();
        for (const auto* side : {&mm.workpiece_chain, &mm.tool_chain})
          for (const model::LinkSpec& k : *side)
            if (k.axis && *k.axis == other) carrier = k.name;
      }
      for (const model::ErrorTermSpec& s : mm.terms)
        if (s.free && !carrier.empty() && s.link == carrier && s.placement == model::ErrorPlacement::location &&
            s.component == carried)
          return true;
      return false;
    }
  return false;
}

}  // namespace

std::vector<std::size_t> free_parameters(const model::ForwardModel& model) {
  std::vector<std::size_t> free;
  const model::MachineModel& mm = model.machine();
  for (std::size_t t = 0; t < mm.terms.size(); ++t) {
    const model::ErrorTermSpec& term = mm.terms[t];
    if (!term.free) continue;
    const bool slope_is_location = slope_is_a_location(mm, term);
    for (Eigen::Index k = 0; k < term.parameters.size(); ++k) {
      // A period is a property of the mechanism (a screw's pitch, 360 deg of a table):
      // fitted only when the file says so (discovery scans it instead).
      if (term.shape.form == TermForm::periodic && k == 0 && !term.free_period) continue;
      // A straightness is the deviation from its axis' line (docs/error-model.md Ref 4: against its
      // least-squares line); the line's slope is where the line lies: the squareness, or
      // nothing where the reference frame defines it.
      if (slope_is_location && k == 1) continue;
      free.push_back(model.parameter_offset(t) + static_cast<std::size_t>(k));
    }
  }
  return free;
}

Eigen::VectorXd model_parameters(const model::ForwardModel& model) {
  Eigen::VectorXd p(static_cast<Eigen::Index>(model.parameter_count()));
  for (std::size_t t = 0; t < model.machine().terms.size(); ++t)
    p.segment(static_cast<Eigen::Index>(model.parameter_offset(t)), model.machine().terms[t].parameters.size()) =
        model.machine().terms[t].parameters;
  return p;
}

void design_matrix(const model::ForwardModel& model, const Eigen::VectorXd& parameters, const MeasurementSet& data,
                   const std::vector<std::size_t>& free, Eigen::VectorXd& r, Eigen::MatrixXd* J) {
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  r.resize(n);
  if (J) J->resize(n, static_cast<Eigen::Index>(free.size()));
  // Rows are independent: each piece of them on a thread, with its own scratch.
  util::for_each_piece(data.observations.size(), util::hardware_threads(), [&](std::size_t begin, std::size_t end) {
    model::ForwardData d(model);
    d.set_parameters(parameters);
    // J's rows gathered a few at a time and stored as a block: a row written straight
    // into the column-major J touches one cache line (and page) per column.
    constexpr Eigen::Index kChunk = 64;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows(J ? kChunk : 0, J ? J->cols() : 0);
    Eigen::Index chunk_begin = static_cast<Eigen::Index>(begin);
    for (auto i = static_cast<Eigen::Index>(begin); i < static_cast<Eigen::Index>(end); ++i) {
      const Observation& o = data.observations[static_cast<std::size_t>(i)];
      model::forward(model, d, o.q, MeasurementSet::conditions(o), J != nullptr);
      const Eigen::Matrix3d& R = d.nominal_chain.oMp.R;  // table frame -> machine axes
      r[i] = o.value - o.direction.dot(R * (d.actual - d.nominal));
      if (!J) continue;
      const Eigen::RowVector3d nR = o.direction.transpose() * R;
      for (std::size_t j = 0; j < free.size(); ++j)
        rows(i - chunk_begin, static_cast<Eigen::Index>(j)) =
            nR * d.J_parameters.col(static_cast<Eigen::Index>(free[j]));
      if (i - chunk_begin + 1 == kChunk || i + 1 == static_cast<Eigen::Index>(end)) {
        J->middleRows(chunk_begin, i - chunk_begin + 1) = rows.topRows(i - chunk_begin + 1);
        chunk_begin = i + 1;
      }
    }
  });
}

namespace {
constexpr std::size_t kRowBlocks = 8;
Eigen::Index block_begin(Eigen::Index rows, std::size_t b) {
  return rows * static_cast<Eigen::Index>(b) / static_cast<Eigen::Index>(kRowBlocks);
}

/// The sum over the fixed row blocks of block(begin, count), computed on the cores and
/// added in block order: the same sums on any machine, whatever its core count.
template <class Block>
Eigen::MatrixXd sum_over_row_blocks(Eigen::Index rows, Eigen::Index out_rows, Eigen::Index out_cols, Block block) {
  std::vector<Eigen::MatrixXd> part(kRowBlocks);
  util::for_each_index(kRowBlocks, util::hardware_threads(), [&](std::size_t b) {
    const Eigen::Index begin = block_begin(rows, b), end = block_begin(rows, b + 1);
    // An empty block adds nothing (and Eigen's product kernels divide by its size).
    part[b] = end > begin ? block(begin, end - begin) : Eigen::MatrixXd::Zero(out_rows, out_cols);
  });
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(out_rows, out_cols);
  for (const Eigen::MatrixXd& p : part) sum += p;
  return sum;
}

}  // namespace

Eigen::MatrixXd normal_matrix(const Eigen::MatrixXd& A, const Eigen::VectorXd* weights) {
  const Eigen::MatrixXd lower =
      sum_over_row_blocks(A.rows(), A.cols(), A.cols(), [&](Eigen::Index begin, Eigen::Index count) {
        Eigen::MatrixXd N = Eigen::MatrixXd::Zero(A.cols(), A.cols());
        if (weights)
          N.selfadjointView<Eigen::Lower>().rankUpdate(
              (weights->segment(begin, count).cwiseSqrt().asDiagonal() * A.middleRows(begin, count)).transpose());
        else
          N.selfadjointView<Eigen::Lower>().rankUpdate(A.middleRows(begin, count).transpose());
        return N;
      });
  return lower.selfadjointView<Eigen::Lower>();
}

Eigen::MatrixXd transpose_product(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  return sum_over_row_blocks(A.rows(), A.cols(), B.cols(), [&](Eigen::Index begin, Eigen::Index count) {
    return Eigen::MatrixXd(A.middleRows(begin, count).transpose() * B.middleRows(begin, count));
  });
}

Eigen::VectorXd residuals(const model::ForwardModel& model, const Eigen::VectorXd& parameters,
                          const MeasurementSet& data) {
  Eigen::VectorXd r;
  design_matrix(model, parameters, data, {}, r, nullptr);
  return r;
}

model::MachineModel without_free_spans(model::MachineModel machine) {
  for (model::ErrorTermSpec& t : machine.terms)
    if (t.free) t.span.reset();
  return machine;
}

std::optional<double> variable_value(const model::Variable& v, const Observation& o) {
  switch (v.kind) {
    case model::VariableKind::axis:
      return o.q[static_cast<Eigen::Index>(v.index)];
    case model::VariableKind::tool_length:
      return o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
    case model::VariableKind::temperature:
      return v.index < o.temperatures.size() ? o.temperatures[v.index] : 20.0;
    case model::VariableKind::time:
      return o.time;
    case model::VariableKind::direction:
    case model::VariableKind::none:
      return std::nullopt;
  }
  return std::nullopt;
}

std::vector<std::optional<model::TermSpan>> fitted_spans(const model::MachineModel& machine,
                                                         const MeasurementSet& data) {
  std::vector<std::optional<model::TermSpan>> spans(machine.terms.size());
  for (std::size_t t = 0; t < machine.terms.size(); ++t) {
    const model::ErrorTermSpec& term = machine.terms[t];
    if (!term.free || !model::term_form(term.shape.form).grows_beyond_data) continue;
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const Observation& o : data.observations)
      if (const std::optional<double> v = variable_value(term.primary, o)) low = std::min(low, *v), high = std::max(high, *v);
    if (low < high) spans[t] = model::TermSpan{low, high};
  }
  return spans;
}

std::string nothing_identifiable(const FitReport& report) {
  if (report.parameters.empty() || report.rank > 0) return {};
  return fmt::format(
      "nothing identifiable above the noise floor: none of the {} free parameters moves the predictions by more than "
      "3 noise sigmas ({:.3f} um) over these {} readings; measure a longer stroke, more targets, more runs or both "
      "directions",
      report.parameters.size(), fit_stages::kSignificant * report.noise * 1e3, report.observations);
}

FitReport fit(const model::ForwardModel& model, const MeasurementSet& data, const FitOptions& options,
              Linearization* at_fit) {
  namespace stages = fit_stages;
  const stages::Problem problem = stages::pose(model, data, options);
  stages::Workspace ws;
  FitReport report;
  stages::open(problem, ws, report);
  stages::hold_blind(problem, report.noise, ws);
  report.converged = problem.unknowns() == 0;
  for (int iteration = 0; iteration < options.max_iterations && !report.converged; ++iteration) {
    report.iterations = iteration + 1;
    if (options.progress)
      options.progress(static_cast<double>(iteration) / static_cast<double>(options.max_iterations));
    report.converged = stages::step(problem, report.noise, iteration, ws) == stages::StepOutcome::converged;
  }
  stages::revert_unsupported(problem, ws, report);
  stages::restore_held(problem, ws, report);
  stages::conclude(problem, ws, report, at_fit);
  if (options.progress) options.progress(1.0);
  return report;
}

}  // namespace ccomp::identify
