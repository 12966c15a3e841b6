#pragma once
// The RS-274/NGC interpreter: executes a program block by block (following subroutine
// calls and loops by seeking in the source), tracks the modal state and offsets, and
// tells a CanonSink every block it executes and every motion that block commands.
// Semantics follow LinuxCNC's rs274ngc; tests/gcode/linuxcnc_suite_test.cpp holds the two
// side by side.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/dialect.hpp"
#include "ccomp/gcode/source.hpp"
#include "ccomp/gcode/tcp_mode.hpp"
#include "ccomp/gcode/tool_table.hpp"

namespace ccomp::gcode {

/// The motions a program reports under cutter radius compensation (G41/G42):
enum class CutterPath : std::uint8_t {
  /// the path the tool centre runs, offset as LinuxCNC's rs274 offsets it, each motion
  /// issued when rs274 issues it (after the next move settles its corner): trace, verify;
  tool_centre,
  /// the programmed path, each motion with the tool centre's move under it, once settled;
  /// the blocks held back with their motions, so each block still comes before its own
  /// (the main job, which leaves the offsetting to the control);
  programmed,
  /// the tool centre's path, blocks held back likewise: each block, then the motions the
  /// offset makes for it, a corner's arc included (the main job's --resolve-cutter-comp).
  tool_centre_by_block,
};

struct InterpreterOptions {
  Dialect dialect;
  ToolTable tools;
  /// LinuxCNC keeps the tool table, work offsets and parameters #5161-#5389 and #5401-#5409
  /// in the machine's units (positions read in program units). rs274 run alone uses inches.
  Units machine_units = Units::mm;
  /// Values only the controller knows (`_hal[...]`, `_ini[...]`, probe results, or any
  /// parameter), by name ("_hal[x.y]") or number ("5063").
  std::vector<std::pair<std::string, double>> parameters;
  /// The work offsets the control holds as the program starts (index 0 is G54 ... 8 is
  /// G59.3; mm and degrees, whatever the machine units): they fill parameters #5221-#5389,
  /// and `parameters` given by number win over them. A system left empty is unknown: a
  /// program that moves a rotary axis in it, without setting it first (G10 L2/L20 or its
  /// parameters), gets one warning that its origin was taken at machine zero.
  std::array<std::optional<Axes>, 9> work_offsets;
  /// Whether that warning is worth giving: false where nothing depends on where program
  /// zero is (a machine model without any error, a trace).
  bool origin_matters = true;
  /// Folders searched for `O<name> call` subroutines in files of their own (name.ngc).
  std::vector<std::string> subroutine_path;
  /// When set, lines starting with `/` are skipped (the operator's block-delete switch).
  bool block_delete = false;
  /// Guards against endless loops: executing more blocks than this is an error (some 20 s
  /// of interpreting), and so is this many blocks in a row without a move.
  std::uint64_t max_blocks = 100'000'000;
  std::uint64_t max_blocks_without_motion = 1'000'000;
  CutterPath cutter_path = CutterPath::tool_centre;
  /// How the codes that switch the control into tool-centre-point kinematics are taken
  /// (gcode/tcp_mode.hpp).
  TcpCodes tcp = TcpCodes::pass;
  /// Under TcpCodes::follow: where the machine is in the other coordinates when TCP switches
  /// on (`to_tcp`: the controlled point, machine frame, as a TCP point) or off, as the
  /// control's kinematics have it under `offsets`, which the interpreter then goes on from
  /// (a block after the switch that names some axes keeps the others where the machine is).
  /// Without it the numbers stay as they are.
  std::function<Axes(const Axes& position, const Offsets& offsets, bool to_tcp)> tcp_switch;
  /// Under TcpCodes::follow, for programs that give the tool's direction (G43.5's I J K, in
  /// the program's frame): `position` (a TCP point) with its rotary axes' angles turned to
  /// where the control's kinematics put that direction, nearest their angles now; nullopt
  /// where the machine cannot take it. Without it G43.5 is refused.
  std::function<std::optional<Axes>(const std::array<double, 3>& direction, const Axes& position,
                                    const Offsets& offsets)>
      tcp_direction;
};

/// Siemens' G group 51: how the tool's direction goes from block to block under TRAORI.
enum class OrientationPath : std::uint8_t {
  vector,  ///< ORIVECT, ORIPLANE: along the great circle
  axes,    ///< ORIAXES: the rotary axes linearly
  other,   ///< a cone, a curve, the path's tangent (ORICONxx, ORICURVE, ORIPATH): not followed
};

/// The modal state an observer may read between blocks (G codes times ten).
struct ModalState {
  int motion = 800;        ///< G80: no motion mode
  int basic_motion = 800;  ///< the last of G0 G1 G2 G3 (Fanuc's G80 returns to it)
  Plane plane = Plane::xy;
  Units units = Units::mm;
  bool absolute = true;       ///< G90 (else G91)
  bool arc_absolute = false;  ///< G90.1 (else G91.1)
  FeedMode feed_mode = FeedMode::units_per_minute;
  int cutter_compensation = 400;  ///< G40, G41, G41.1, G42, G42.1
  int tool_length_mode = 490;     ///< G49, G43, G43.1, G43.2
  /// The code tool centre point control is on by (TcpCodes::follow): 434 (G43.4, off again
  /// with G43, G43.1, G43.2 or G49, its group's), 435 (G43.5, the same, the tool's direction
  /// given as I J K), 128 (M128, off with M129), 428 (M428, off
  /// with M429: LinuxCNC's kinematics switch, which G43 and G49 leave as it is), kTraoriTcp
  /// (Siemens' TRAORI, off with TRAFOOF); 0 off. Under
  /// it the axis words are the tool tip in the part and the rotary axes' angles (Motion::tcp).
  int tcp = 0;
  /// Siemens' orientation interpolation under TRAORI, which G group 25 (ORIWKS, the basic
  /// setting, or ORIMKS) decides on some controls and G group 51 (ORIVECT, its basic setting,
  /// ORIAXES or the rest) on others (machine data MD21104): ORIWKS with ORIVECT turns the
  /// tool's direction along a great circle, ORIMKS with ORIAXES moves the rotary axes
  /// linearly; a pair that disagrees is the machine data's to settle.
  bool orientation_in_machine = false;  ///< ORIMKS (else ORIWKS)
  OrientationPath orientation_path = OrientationPath::vector;
  /// Under TRAORI the program gives the tool's direction as A3= B3= C3= (since its last block
  /// that gave any), not the rotary axes' angles.
  bool siemens_vectors = false;
  /// The tool's cutting edge in force (Dialect::d_selects_cutting_edge): 0 none.
  int cutting_edge = 0;
  bool retract_to_r = true;       ///< G99 (else G98: back to the initial level)
  int path_mode = 640;
  double feed = 0.0;  ///< mm/min (or inverse time, or mm/rev)
  double speed = 0.0;
  int spindle = 0;  ///< 1 clockwise (M3), -1 counter-clockwise (M4), 0 stopped (M5, M6)
  int tool = 0;
  int selected_tool = -1;
};

class Interpreter {
 public:
  explicit Interpreter(InterpreterOptions options = {});
  ~Interpreter();
  Interpreter(Interpreter&&) noexcept;
  Interpreter& operator=(Interpreter&&) noexcept;

  /// Executes the whole program. Throws ccomp::Error naming the file, line and column.
  void run(LineSource& source, CanonSink& sink);

  [[nodiscard]] const ModalState& modal() const;
  [[nodiscard]] const Offsets& offsets() const;
  /// The controlled point now (machine frame, no tool length), mm and degrees.
  [[nodiscard]] const Axes& position() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ccomp::gcode
