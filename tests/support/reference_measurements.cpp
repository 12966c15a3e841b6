#include "reference_measurements.hpp"

#include <fmt/format.h>

#include "ccomp/model/model_file.hpp"

namespace ccomp::test {

std::string reference_csv(const ReferenceHmc& machine, const std::vector<ReferenceReading>& readings,
                          FrameGiven how) {
  std::string out;
  const Eigen::Vector3d& o = machine.work_origin;
  if (how == FrameGiven::in_file) out += fmt::format("# frame: program G54 X{} Y{} Z{}\n", o.x(), o.y(), o.z());
  if (how == FrameGiven::by_option) out += "# frame: program G54\n";
  out += "x,y,z,b,L,t,T_spindle,T_bed,vx,vy,vz,nx,ny,nz,d,source\n";
  for (const ReferenceReading& r : readings) {
    const Eigen::Vector3d p = machine.program_of_axes(Eigen::Vector3d(r.x, r.y, r.z), r.L);
    out += fmt::format("{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.3f},{:.9f},{:.9f},{:g},{:g},{:g},{:.17g},{:.17g},{:.17g},{:.17g},{}\n",
                       p.x(), p.y(), p.z(), r.b_deg, r.L, r.time, r.state.spindle_T, r.state.bed_T,
                       r.state.approach[0], r.state.approach[1], r.state.approach[2], r.direction.x(), r.direction.y(),
                       r.direction.z(), r.value, r.source);
  }
  return out;
}

identify::MeasurementSet reference_measurements(const ReferenceHmc& machine,
                                                const std::vector<ReferenceReading>& readings, FrameGiven how) {
  // What the reader needs of a model: the axes, the sensors in the file's order and, given
  // that way, the work offsets.
  std::string model_text = "name: reader\naxes: {X: {}, Y: {}, Z: {}, B: {type: rotary}}\nsensors: [spindle, bed]\n";
  if (how == FrameGiven::by_model)
    model_text += fmt::format("work_offsets: {{G54: {{X: {}, Y: {}, Z: {}}}}}\n", machine.work_origin.x(),
                              machine.work_origin.y(), machine.work_origin.z());
  const model::MachineModel reader = model::parse_machine_model(model_text, "reader.yaml");
  identify::ReadOptions options;
  options.tool_length = 100.0;
  if (how == FrameGiven::by_option) {
    identify::MeasurementFrame frame;
    frame.origin = model::WorkOrigin{machine.work_origin.x(), machine.work_origin.y(), machine.work_origin.z()};
    options.frame = frame;
  }
  identify::MeasurementSet set;
  identify::parse_measurements(reference_csv(machine, readings, how), "reference.csv", reader, options, set);
  return set;
}

}  // namespace ccomp::test
