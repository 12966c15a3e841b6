#pragma once
// The machine model file (YAML, docs/machine-model.md): reading one into a MachineModel,
// and writing fitted parameters or more terms back into its text. The model itself, plain
// data, is ccomp/model/machine.hpp; this is the one place that knows the file.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "ccomp/model/machine.hpp"

namespace ccomp::model {

/// Reads and validates a model file. Throws ccomp::Error (model) naming the file, the key
/// and the bad value.
[[nodiscard]] MachineModel load_machine_model(const std::string& path);
[[nodiscard]] MachineModel parse_machine_model(const std::string& text, const std::string& name);

/// The model file's text with new parameter values for its terms (one vector per term, in
/// internal units; written back in the file's units) and `record` (YAML lines, a mapping)
/// under a top-level `fitted:` key. `spans`, where given (one per term), is written as
/// each such term's `span` in its variable's unit; the others keep theirs. Comments do not
/// survive: yaml-cpp does not keep them.
[[nodiscard]] std::string rewrite_parameters(const std::string& text, const MachineModel& model,
                                             const std::vector<Eigen::VectorXd>& parameters, const std::string& record,
                                             const std::vector<std::optional<TermSpan>>& spans = {});

/// The model file's text with more terms (each a YAML mapping, one line: what `ccomp check`
/// suggests) appended to its `terms`. Throws ccomp::Error (usage) for a spec that is not
/// a mapping.
[[nodiscard]] std::string add_terms(const std::string& text, const std::vector<std::string>& specs,
                                    const std::string& name);

/// The model with more terms, each a one-line YAML mapping (what `ccomp check` suggests),
/// read as the model file's own terms are, and with any sensor a term names that the
/// model lacks: the model `add_terms` would write, without a text to write it into.
/// Throws ccomp::Error (model) for a spec that is not a valid term, `name` as its file.
[[nodiscard]] MachineModel with_terms(MachineModel model, const std::vector<std::string>& specs,
                                      const std::string& name);

}  // namespace ccomp::model
