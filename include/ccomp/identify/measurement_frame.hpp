#pragma once
// The frame a measurement file's positions are in. A row's x, y, z (and rotary angles) are
// program coordinates, relative to a work offset (the tool length applied: the tool tip's
// point), unless the file says `# frame: machine`: the control's machine coordinates, the
// axis positions themselves (G53; no work offset, no tool length). The frame decides where
// each reading lies from the rotary lines, and so the lever of every rotary error.
//
// A file states its frame in a comment line before its header:
//   # frame: program G54 X0 Y0 Z-400   (program coordinates; G54's origin, given here)
//   # frame: program G54               (G54's origin from --work-offset or the model)
//   # frame: machine
#include <optional>
#include <string>
#include <string_view>

#include "ccomp/model/machine.hpp"
#include "ccomp/model/work_offsets.hpp"

namespace ccomp::identify {

enum class FrameKind : std::uint8_t { program, machine };

struct MeasurementFrame {
  FrameKind kind = FrameKind::program;
  std::size_t system = 1;                  ///< program frames: G54 = 1 ... G59.3 = 9
  std::optional<model::WorkOrigin> origin; ///< where the file (or the user) gives it
};

/// Whether a comment line (starting with '#') states a frame.
[[nodiscard]] bool is_frame_line(std::string_view line);
/// The frame a `# frame: ...` line states. Throws ccomp::Error (data) at `file`:`line`,
/// naming what is wrong.
[[nodiscard]] MeasurementFrame parse_frame_line(std::string_view text, const std::string& file, std::uint32_t line);

/// Where the file's program zero lies in machine coordinates, from what the file says,
/// what the user said (`given`: --frame, --work-offset) and the model's work offsets:
/// the file's own numbers first; a user's that contradict them are refused (data); else
/// the user's, else the model's; else machine zero, with `unknown` set (said once where a
/// rotary axis turns). A machine frame has no origin (all zeros).
struct ResolvedFrame {
  MeasurementFrame frame;
  model::WorkOrigin origin{};
  bool unknown = false;
};
[[nodiscard]] ResolvedFrame resolve_frame(const std::optional<MeasurementFrame>& in_file,
                                          const std::optional<MeasurementFrame>& given,
                                          const model::MachineModel& model, const std::string& file);

/// The `# frame: ...` line that says `frame` with its origin written out.
[[nodiscard]] std::string frame_line(const ResolvedFrame& frame);

}  // namespace ccomp::identify
