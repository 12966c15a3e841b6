// libFuzzer target: measurement CSV files (identify::parse_measurements, what
// read_measurements does with a file's text), read against the sample HMC model (sensors,
// a rotary axis) and summarised as fit and check do next.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "fuzz_outcome.hpp"

namespace {

const ccomp::model::MachineModel& hmc() {
  static const ccomp::model::MachineModel model =
      ccomp::model::load_machine_model(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb.yaml");
  return model;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ccomp::model::MachineModel& model = hmc();
  return ccomp::fuzz::read_or_refuse([&] {
    ccomp::identify::MeasurementSet set;
    ccomp::identify::parse_measurements(std::string(reinterpret_cast<const char*>(data), size), "fuzz.csv", model, {},
                                        set);
    ccomp::identify::summarize(set, model);
  });
}
