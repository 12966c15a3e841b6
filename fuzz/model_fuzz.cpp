// libFuzzer target: machine model files (model::parse_machine_model), as -m reads them. A
// model the reader accepts is also built into the forward model and evaluated, as every
// command that takes a model does next: accepting a model it cannot use is a reader's bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "fuzz_outcome.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ccomp::fuzz::read_or_refuse([&] {
    using namespace ccomp::model;
    const MachineModel machine =
        parse_machine_model(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
    const ForwardModel model(machine);
    ForwardData scratch(model);
    Conditions conditions;
    conditions.temperatures.assign(machine.sensors.size(), 20.0);
    forward(model, scratch, ChainQ::Zero(), conditions, true);
    forward(model, scratch, ChainQ::Constant(1.0), conditions);
  });
}
