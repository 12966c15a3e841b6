#pragma once
// Test support: the reference machine's readings (reference_hmc.hpp) as a measurement file
// of the CSV contract, in the reference's program coordinates (its own work origin), read
// back by ccomp's reader: x y z of the tool tip, b, L, approach, time, the spindle's and the
// bed's sensors (`T_spindle`, `T_bed`, whether or not a model has them), one source per plan.
#include <string>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"
#include "reference_five_axis.hpp"
#include "reference_hmc.hpp"

namespace ccomp::test {

/// How the file tells ccomp where its program zero is (docs/identification.md, "Frames").
enum class FrameGiven : std::uint8_t {
  in_file,    ///< `# frame: program G54 X.. Y.. Z..`
  by_option,  ///< `# frame: program G54`, the origin as --work-offset gives it
  by_model,   ///< no frame line: the model's work_offsets (the reader's model gets them)
};

/// The readings as the file a metrology engineer would write (program coordinates).
[[nodiscard]] std::string reference_csv(const ReferenceHmc& machine, const std::vector<ReferenceReading>& readings,
                                        FrameGiven how = FrameGiven::in_file);

/// That file read by ccomp's reader, the frame given `how`.
[[nodiscard]] identify::MeasurementSet reference_measurements(const ReferenceHmc& machine,
                                                              const std::vector<ReferenceReading>& readings,
                                                              FrameGiven how = FrameGiven::in_file);

/// A five-axis reference probed at `poses` (chain values: machine axis positions, the tool
/// length last, as identify::sphere_poses gives them; `rotary` the rotary axes' letters, upper
/// case): the file in the reference's program coordinates (its own work offset, written in
/// the `# frame:` line), one row per reading along X, Y and Z of the machine, each the tool
/// tip's deviation from where the program meant it plus Gaussian noise of `noise` mm.
[[nodiscard]] std::string five_axis_csv(const ReferenceFiveAxis& machine, const std::vector<model::ChainQ>& poses,
                                        const std::string& rotary, double noise, unsigned seed);

}  // namespace ccomp::test
