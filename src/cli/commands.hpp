#pragma once
// The subcommands of the ccomp CLI: argument structs, their CLI11 wiring and their runs.
#include <CLI/CLI.hpp>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/work_offsets.hpp"

namespace ccomp::cli {

/// Options every command that reads G-code shares.
struct ProgramArgs {
  std::string tool_table;
  std::string machine_units = "mm";
  std::vector<std::string> params;  ///< NAME=VALUE
  std::string dialect;              ///< empty: the model's, else linuxcnc
  std::vector<std::string> sub_path;
  bool block_delete = false;
  std::uint64_t max_blocks = 0;  ///< 0: the interpreter's own limit
  std::vector<std::string> work_offsets;  ///< --work-offset G54=X-250,Y0,Z-300
};
void add_program_options(CLI::App& cmd, ProgramArgs& args);
/// --tolerance's transform: mm, or a length with its unit ("1um"); a bare number beyond 0.1 mm
/// is refused as the micrometres it likely means (model::rules::tolerance()).
[[nodiscard]] CLI::Validator tolerance_in_mm();
/// --angular-tolerance: a finite number of microradians above 0.
[[nodiscard]] CLI::Validator angle_in_urad();
/// --time: a finite number of seconds, 0 or more (a warm-up does not run backwards).
[[nodiscard]] CLI::Validator seconds_since_warm_up();
/// --work-offset's systems (usage errors name the option).
[[nodiscard]] model::WorkOffsets work_offsets_of(const std::vector<std::string>& specs);
/// Interpreter options from the shared arguments; `model_dialect` when none is given. The
/// work offsets the program starts with: `base` (the model's, or a compensated program's
/// header), with --work-offset's systems over them (and --param's numbers over those).
[[nodiscard]] gcode::InterpreterOptions interpreter_options(const ProgramArgs& args, const std::string& model_dialect,
                                                            const model::WorkOffsets& base = {});

/// --hold AXIS[=auto|clamped|free] (repeatable).
void add_hold_option(CLI::App& cmd, std::vector<std::string>& holds);
/// The model with --hold's axes set (usage errors for an axis that is not a rotary one).
[[nodiscard]] model::MachineModel with_holds(model::MachineModel m, const std::vector<std::string>& specs);
/// "B held (the program does not turn it)" for the axes `held` names.
[[nodiscard]] std::string held_axes_text(const model::MachineModel& m, AxisSet held);

struct CompensateArgs {
  std::vector<std::string> inputs;
  std::string model;
  std::string output;
  std::string out_dir;
  bool in_place = false;
  std::string backup_suffix = ".orig";
  int jobs = 1;
  int threads = 0;  ///< per program, 1 or 2; 0: 2 when the machine has a core for each
  bool force = false;
  bool expand_cycles = false;
  bool resolve_cutter_comp = false;
  bool flatten = false;
  bool progress = false;
  double tolerance = 0.001;
  bool exact = false;
  int decimals = -1;                 ///< -1: the program's own
  int rotary_decimals = -1;          ///< -1: the program's own
  std::vector<std::string> sensors;  ///< NAME=VALUE (degC)
  std::optional<double> time;  ///< --time, s; none given: a warm-up term is refused
  std::vector<std::string> holds;  ///< --hold AXIS[=MODE]
  bool quiet = false;
  bool json = false;
  ProgramArgs program;
};
void add_compensate(CLI::App& app, CompensateArgs& args);
int run_compensate(const CompensateArgs& args);

struct CheckArgs {
  std::string input;
  std::string compensated;
  std::string model;
  std::vector<std::string> sensors;
  std::optional<double> time;  ///< --time, s; none given: a warm-up term is refused
  int samples = 8;
  double tolerance = 0.0;  ///< verify: mm; 0: the one in the output's header, else 0.001
  /// verify: urad the tool's direction may be off; 0: the tolerance over kFlankReachMm.
  double angular_tolerance_urad = 0.0;
  bool json = false;
  ProgramArgs program;
};
CLI::App* add_predict(CLI::App& app, CheckArgs& args);
CLI::App* add_verify(CLI::App& app, CheckArgs& args);
int run_predict(const CheckArgs& args);
int run_verify(const CheckArgs& args);

struct TraceArgs {
  std::string input;
  bool json = false;
  ProgramArgs program;
};
CLI::App* add_trace(CLI::App& app, TraceArgs& args);
int run_trace(const TraceArgs& args);
/// flatten: the program as it runs (gcode::flatten()), on standard output.
CLI::App* add_flatten(CLI::App& app, TraceArgs& args);
int run_flatten(const TraceArgs& args);

/// fit, check and simulate: the model against measurements.
struct IdentifyArgs {
  std::vector<std::string> measurements;
  std::string model;
  std::string output;
  std::vector<std::string> weights;  ///< SOURCE=W
  std::vector<std::string> add;      ///< terms to add (YAML flow mappings)
  bool robust = false;
  bool json = false;
  std::string report;  ///< check: the HTML page to write
  double tool_length = 100.0;
  std::string frame;                      ///< --frame: program or machine
  std::vector<std::string> work_offsets;  ///< --work-offset G54=X..,Y..,Z..
  // simulate
  std::vector<std::string> plans{"nine_lines"};
  double noise_um = 0.2;
  unsigned seed = 1;
  double step = 25.0;
  double rotary_step = 15.0;
  int runs = 1;
  // positioning
  std::string axis;
  std::string source;
  std::string angle_unit = "arcsec";  ///< a rotary axis' deviations: arcsec or urad
  std::string instrument, uncertainty;  ///< what the report states, over the files'
  std::vector<std::string> temperatures;  ///< NAME=DEGC
  // one-axis instrument files (import, and every command reading measurements)
  std::vector<std::string> at;  ///< AXIS=VALUE[,AXIS=VALUE]
  std::string unit;             ///< the deviations' unit where the file states none
};
/// --axis (when `with_axis`), --at and --unit: what a one-axis instrument file needs to be placed.
void add_reading_options(CLI::App& cmd, IdentifyArgs& args, bool with_axis);
/// --frame and --work-offset: the frame of measurement files that do not state their own.
void add_frame_options(CLI::App& cmd, IdentifyArgs& args);
/// The frame the user gives the files (nothing when neither option is given).
[[nodiscard]] std::optional<identify::MeasurementFrame> frame_of(const IdentifyArgs& args);
/// The reader's options from the command line (usage errors for a bad --at or --axis).
[[nodiscard]] identify::ReadOptions reading_options(const IdentifyArgs& args);
/// import: an instrument's file converted to the measurement contract.
CLI::App* add_import(CLI::App& app, IdentifyArgs& args);
int run_import(const IdentifyArgs& args);
CLI::App* add_fit(CLI::App& app, IdentifyArgs& args);
CLI::App* add_check(CLI::App& app, IdentifyArgs& args);
CLI::App* add_simulate(CLI::App& app, IdentifyArgs& args);
int run_fit(const IdentifyArgs& args);
int run_check(const IdentifyArgs& args);
int run_simulate(const IdentifyArgs& args);
CLI::App* add_positioning(CLI::App& app, IdentifyArgs& args);
CLI::App* add_nine_line(CLI::App& app, IdentifyArgs& args);
int run_nine_line(const IdentifyArgs& args);
int run_positioning(const IdentifyArgs& args);

/// plan: the next measurement for programs (identify/plan.hpp).
struct PlanArgs {
  IdentifyArgs identify;  ///< the measurements, the model, -o, --json, --tool-length, --frame
  std::vector<std::string> programs;
  std::size_t budget = 300;
  std::vector<std::string> sensors;  ///< NAME=VALUE (degC)
  std::optional<double> time;
  ProgramArgs program;
};
CLI::App* add_plan(CLI::App& app, PlanArgs& args);
int run_plan(const PlanArgs& args);

/// export: a model as a control's compensation tables.
struct ExportArgs {
  std::string model;
  std::string control;
  std::string axis;
  std::string output = "-";
  double step = 0.0;  ///< mm; 0: the finest the control holds
  double from = std::numeric_limits<double>::quiet_NaN(), to = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> at;  ///< AXIS=VALUE
  double tool_length = 100.0;
  std::vector<std::string> sensors;
  double time = 0.0;
  int comp_file_type = 0;
  int axis_number = 0;
  double fanuc_unit = 0.001;
  int fanuc_reference_point = 0;
  bool json = false;
};
CLI::App* add_export(CLI::App& app, ExportArgs& args);
int run_export(const ExportArgs& args);

}  // namespace ccomp::cli
