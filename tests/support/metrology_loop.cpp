#include "metrology_loop.hpp"

#include "ccomp/model/model_file.hpp"

namespace ccomp::test {
namespace {

/// `text` with the fit's values written back, as `ccomp fit -o` writes them.
std::string fitted_text(const std::string& text, const model::MachineModel& m, const identify::FitReport& r) {
  const model::ForwardModel f(m);
  std::vector<Eigen::VectorXd> per_term;
  for (std::size_t t = 0; t < m.terms.size(); ++t)
    per_term.push_back(
        r.all_parameters.segment(static_cast<Eigen::Index>(f.parameter_offset(t)), m.terms[t].parameters.size()));
  return model::rewrite_parameters(text, m, per_term, "{by: follow_the_loop}");
}

}  // namespace

LoopResult follow_the_loop(std::string text, const identify::MeasurementSet& data, int rounds,
                           const identify::FitOptions& options) {
  LoopResult out;
  auto refit = [&] {
    const model::MachineModel m = model::parse_machine_model(text, "fitted.yaml");
    out.last = identify::fit(model::ForwardModel(m), data, options);
    out.refusals.insert(out.refusals.end(), out.last.refusals.begin(), out.last.refusals.end());
    if (out.last.refusals.empty()) text = fitted_text(text, m, out.last);  // a refused fit is not written
  };
  refit();
  for (int round = 0; round <= rounds; ++round) {
    identify::DiagnoseOptions diagnose_options;
    diagnose_options.fit = options;  // check --robust, as fit
    const identify::Diagnosis d = identify::diagnose(
        model::ForwardModel(model::parse_machine_model(text, "fitted.yaml")), data, diagnose_options);
    for (const identify::Tie& t : d.ties) out.ties.push_back(t.measurement);
    if (d.suggestions.empty()) {
      out.ended = true;
      out.unexplained = d.unexplained;
      break;
    }
    if (round == rounds) break;
    out.added.push_back(d.suggestions.front().spec);
    text = model::add_terms(text, {d.suggestions.front().spec}, "fitted.yaml");
    refit();
  }
  out.text = text;
  return out;
}

}  // namespace ccomp::test
