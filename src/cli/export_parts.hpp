#pragma once
// What ccomp export's two kinds of table (along an axis: export.cpp; over the volume:
// export_volume.cpp) share: where the machine stands, what the model holds that a table
// cannot, and the summary's pieces.
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/controller/axis_table.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/util/json.hpp"
#include "commands.hpp"

namespace ccomp::cli {

/// The line the tables are taken along: each other axis at --at's value, else at 0 when
/// its travel holds 0, else mid-travel; rotary axes at 0; the tool length of
/// --tool-length. `axis` is the table's own (0: none): an --at for it is refused when
/// `own_table`, else left out.
model::ChainQ table_line(const model::MachineModel& m, const ExportArgs& args, char axis, bool own_table);

/// What the model holds that no table of a control carries, by term (each term once, in
/// the first of these that holds it). `cross`: whether the control has cross tables.
struct Uncarried {
  std::vector<std::string> thermal, rotary, straightness, off_line;
};
Uncarried uncarried_terms(const model::MachineModel& m, bool cross);

std::string joined(const std::vector<std::string>& names);
void json_names(util::JsonWriter& j, std::string_view key, const std::vector<std::string>& names);
void json_residual(util::JsonWriter& j, std::string_view key, const controller::Residual& r);

/// Warns on stderr, once a term, of each term the table uses beyond where it was fitted
/// (it holds its value at the span's end there: model/term_span.hpp), the axes over
/// [low, high] (chain values) under `conditions`.
void warn_beyond_spans(const model::MachineModel& m, const model::ChainQ& low, const model::ChainQ& high,
                       const model::Conditions& conditions);

/// ccomp export --control isg: the volumetric table.
int run_volume_export(const ExportArgs& args);

}  // namespace ccomp::cli
