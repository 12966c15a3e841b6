// libFuzzer target: instruments' files, each reader on its own (a Renishaw .rtl, a one-axis
// table), read against the geometric sample HMC (X Y Z and a rotary B) and converted into
// the contract as fit and check do. The input's first byte picks the reader, the axis a file
// that names none is taken for (X or B), whether --unit um is given and where the other axes
// stood. Run on 2026-11-28 (clang 14, ASan + UBSan, seeds: the samples behind each choice
// byte): 1,040,558 executions in 90 s, nothing found.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "ccomp/identify/measurement_formats.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "fuzz_outcome.hpp"

namespace {

const ccomp::model::MachineModel& hmc() {
  static const ccomp::model::MachineModel model =
      ccomp::model::load_machine_model(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb-geometric.yaml");
  return model;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t choice = data[0];
  const ccomp::identify::io::MeasurementFormat& format =
      choice & 1 ? ccomp::identify::io::renishaw_rtl_format() : ccomp::identify::io::axis_table_format();
  ccomp::identify::ReadOptions options;
  options.tool_length = 100.0;
  options.axis = choice & 2 ? 'B' : 'X';
  if (choice & 4) options.unit = "um";
  if (choice & 8) options.at = {{'Y', -360.0}, {'Z', -400.0}};
  return ccomp::fuzz::read_or_refuse([&] {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
    ccomp::identify::MeasurementSet set;
    format.read(in, "fuzz.txt", hmc(), options, set);
    ccomp::identify::summarize(set, hmc());
  });
}
