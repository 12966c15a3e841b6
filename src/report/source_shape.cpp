#include "report/source_shape.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <numbers>

#include "ccomp/axis.hpp"
#include "ccomp/util/interval.hpp"

namespace ccomp::report {

char axis_letter(std::size_t axis) {
  return kAxisLetters[axis];
}

double axis_value(const identify::Observation& o, std::size_t axis) {
  // The chain's own variable, as the model's terms read it: Z with the tool length in it.
  const double q = o.q[static_cast<Eigen::Index>(axis)];
  return angular_at(axis) ? q * 180.0 / std::numbers::pi : q;
}

std::string position_title(std::size_t axis) {
  return fmt::format("{} axis position, machine ({})", axis_letter(axis), angular_at(axis) ? "deg" : "mm");
}

std::string frame_note(const identify::MeasurementSet& data, std::size_t reading) {
  const identify::Observation& o = data.observations[reading];
  const std::string positions =
      "Positions are the machine's axis positions (G53, as the control shows them and the model's terms read them)";
  if (o.file >= data.frames.size()) return positions + ".";
  const identify::ResolvedFrame& f = data.frames[o.file];
  const std::string file = o.file < data.files.size() ? data.files[o.file] : std::string("the file");
  const double tool = o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
  if (f.frame.kind == identify::FrameKind::machine)
    return fmt::format("{}; {} is in machine coordinates too.", positions, file);
  std::string origin;
  for (std::size_t i = 0; i < 3; ++i) origin += fmt::format("{}{} {:g}", i == 0 ? "" : ", ", axis_letter(i), f.origin[i]);
  return fmt::format(
      "{}; {} gives program coordinates of {} (origin {} mm{}): its x = X &minus; {:g}, y = Y &minus; {:g}, "
      "z = Z &minus; {:g} &minus; L (L {:g} mm).",
      positions, file, model::coordinate_system_name(f.frame.system), origin, f.unknown ? ", which nobody gave" : "",
      f.origin[0], f.origin[1], f.origin[2], tool);
}

std::string kind_name(SourceKind kind) {
  switch (kind) {
    case SourceKind::line:
      return "line";
    case SourceKind::rotary:
      return "rotary";
    case SourceKind::volumetric:
      return "volumetric";
  }
  return "";
}

std::vector<SourceShape> source_shapes(const identify::MeasurementSet& data, const model::MachineModel& model) {
  std::vector<SourceShape> shapes(data.sources.size());
  for (std::size_t i = 0; i < data.observations.size(); ++i) shapes[data.observations[i].source].readings.push_back(i);
  for (SourceShape& s : shapes) {
    std::vector<std::size_t> linear_moving, rotary_moving;
    for (const model::AxisSpec& a : model.axes) {
      const auto axis = static_cast<std::size_t>(a.index());
      util::Interval range;
      for (std::size_t i : s.readings) range.add(axis_value(data.observations[i], axis));
      if (range.width() > 1e-6) (angular_at(axis) ? rotary_moving : linear_moving).push_back(axis);
    }
    util::Interval tool;
    for (std::size_t i : s.readings)
      tool.add(data.observations[i].q[static_cast<Eigen::Index>(model::kToolLengthIndex)]);
    if (!rotary_moving.empty())
      s.kind = SourceKind::rotary, s.axis = rotary_moving.front();
    else if (linear_moving.size() == 1 && !(tool.width() > 1e-6))
      s.kind = SourceKind::line, s.axis = linear_moving.front();
    else
      s.kind = SourceKind::volumetric;
  }
  return shapes;
}

std::vector<ReadingDirection> reading_directions(const identify::MeasurementSet& data,
                                                 const std::vector<std::size_t>& readings) {
  std::map<std::string, ReadingDirection> by_label;
  for (std::size_t i : readings) {
    const Eigen::Vector3d& n = data.observations[i].direction;
    int axis = -1;
    for (int k = 0; k < 3; ++k)
      if (std::abs(std::abs(n[k]) - 1.0) < 1e-6) axis = k;
    const std::string label =
        axis >= 0 ? std::string(1, "XYZ"[axis]) : fmt::format("({:.3g}, {:.3g}, {:.3g})", n[0], n[1], n[2]);
    ReadingDirection& d = by_label[label];
    d.label = label, d.axis = axis;
    d.readings.push_back(i);
    d.sign.push_back(axis >= 0 && n[axis] < 0 ? -1.0 : 1.0);
  }
  std::vector<ReadingDirection> out;
  for (auto& [label, d] : by_label) out.push_back(std::move(d));
  return out;
}

}  // namespace ccomp::report
