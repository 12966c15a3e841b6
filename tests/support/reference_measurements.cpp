#include "reference_measurements.hpp"

#include <fmt/format.h>

#include <numbers>
#include <random>

#include "ccomp/model/model_file.hpp"

namespace ccomp::test {

std::string reference_csv(const ReferenceHmc& machine, const std::vector<ReferenceReading>& readings, FrameGiven how) {
  std::string out;
  const Eigen::Vector3d& o = machine.work_origin;
  if (how == FrameGiven::in_file) out += fmt::format("# frame: program G54 X{} Y{} Z{}\n", o.x(), o.y(), o.z());
  if (how == FrameGiven::by_option) out += "# frame: program G54\n";
  out += "x,y,z,b,L,t,T_spindle,T_bed,vx,vy,vz,vb,nx,ny,nz,d,source\n";
  for (const ReferenceReading& r : readings) {
    const Eigen::Vector3d p = machine.program_of_axes(Eigen::Vector3d(r.x, r.y, r.z), r.L);
    out += fmt::format(
        "{:.9f},{:.9f},{:.9f},{:.9f},{:.9f},{:.3f},{:.9f},{:.9f},{:g},{:g},{:g},{:g},{:.17g},{:.17g},{:.17g},{:.17g},{}\n",
        p.x(), p.y(), p.z(), r.b_deg, r.L, r.time, r.state.spindle_T, r.state.bed_T, r.state.approach[0],
        r.state.approach[1], r.state.approach[2], r.state.b_approach, r.direction.x(), r.direction.y(), r.direction.z(), r.value, r.source);
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

namespace {
/// The machine's X, Y and Z as seen in the part at the pose: the nominal tip's move (part
/// frame) for a millimetre of each word, so no knowledge of the reference's chain is needed.
Eigen::Matrix3d part_from_machine(const ReferenceFiveAxis& machine, const FiveAxisWords& w, double L) {
  Eigen::Matrix3d R;
  const Eigen::Vector3d at = machine.nominal(w, L).tip;
  for (int k = 0; k < 3; ++k) {
    FiveAxisWords moved = w;
    (k == 0 ? moved.x : k == 1 ? moved.y : moved.z) += 1.0;
    R.col(k) = machine.nominal(moved, L).tip - at;
  }
  return R;
}
}  // namespace

std::string five_axis_csv(const ReferenceFiveAxis& machine, const std::vector<model::ChainQ>& poses,
                          const std::string& rotary, double noise, unsigned seed) {
  constexpr double kDegPerRad = 180.0 / std::numbers::pi;
  const Eigen::Vector3d o = machine.work_offset();
  std::string out = fmt::format("# frame: program G54 X{:.17g} Y{:.17g} Z{:.17g}\nx,y,z", o.x(), o.y(), o.z());
  for (const char r : rotary) out += fmt::format(",{}", static_cast<char>(r - 'A' + 'a'));
  out += ",L,nx,ny,nz,d,source\n";
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  for (const model::ChainQ& q : poses) {
    const double L = q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
    const FiveAxisWords w{q[0] - o.x(),      q[1] - o.y(),      q[2] - L - o.z(),
                          q[3] * kDegPerRad, q[4] * kDegPerRad, q[5] * kDegPerRad};
    const Eigen::Vector3d in_part = machine.actual(w, L).tip - machine.nominal(w, L).tip;
    const Eigen::Vector3d in_machine = part_from_machine(machine, w, L).transpose() * in_part;
    for (int k = 0; k < 3; ++k) {
      out += fmt::format("{:.9f},{:.9f},{:.9f}", w.x, w.y, w.z);
      for (const char r : rotary) out += fmt::format(",{:.9f}", r == 'A' ? w.a : r == 'B' ? w.b : w.c);
      const Eigen::Vector3d n = Eigen::Vector3d::Unit(k);
      out += fmt::format(",{:g},{:g},{:g},{:g},{:.17g},sphere\n", L, n.x(), n.y(), n.z(), in_machine[k] + gauss(rng));
    }
  }
  return out;
}

}  // namespace ccomp::test
