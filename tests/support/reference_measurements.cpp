#include "reference_measurements.hpp"

#include <algorithm>
#include <numbers>

namespace ccomp::test {

identify::MeasurementSet reference_measurements(const std::vector<ReferenceReading>& readings) {
  identify::MeasurementSet set;
  set.files = {"reference.csv"};
  set.sensors = {"spindle", "bed"};
  for (const ReferenceReading& r : readings) {
    identify::Observation o;
    o.q << r.x, r.y, r.z, 0, r.b_deg * std::numbers::pi / 180.0, 0, 0, 0, 0, r.L;
    for (std::size_t i = 0; i < 3; ++i) o.directions[i] = r.state.approach[i];
    o.temperatures = {r.state.spindle_T, r.state.bed_T};
    o.time = r.time;
    o.direction = r.direction;
    o.value = r.value;
    auto at = std::find(set.sources.begin(), set.sources.end(), r.source);
    if (at == set.sources.end()) at = set.sources.insert(set.sources.end(), r.source);
    o.source = static_cast<std::uint32_t>(at - set.sources.begin());
    o.row = static_cast<std::uint32_t>(set.observations.size() + 2);
    set.observations.push_back(o);
  }
  return set;
}

}  // namespace ccomp::test
