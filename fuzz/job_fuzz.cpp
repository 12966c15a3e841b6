// libFuzzer target: the main job end to end on G-code programs: read, interpreted,
// compensated on the sample HMC (46 terms, backlash, thermal) and rewritten; then what the
// written program makes the machine do measured against the original (verify), and the
// original's uncompensated error (predict). The readers' targets stop at the interpreter;
// this one reaches what only the commands do with a program: the inverse on its points,
// splits and take-ups, the rewriting of its words in their own number style, the search of
// the original's path for every executed point.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <typeinfo>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/gcode/dialect.hpp"
#include "ccomp/gcode/source.hpp"
#include "ccomp/gcode/tool_table.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "fuzz_outcome.hpp"

namespace {

using namespace ccomp;

const model::MachineModel& sample_machine() {
  static const model::MachineModel machine =
      model::load_machine_model(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb.yaml");
  return machine;
}

const gcode::ToolTable& sample_tools() {
  static const gcode::ToolTable tools = [] {
    std::istringstream in("T1 P1 Z100.0 D10.0\nT2 P2 Z120.0 D6.0\nT3 P3 Z90.0 D8.0 X0.5\n");
    return gcode::read_tool_table(in, "fuzz.tbl");
  }();
  return tools;
}

/// Bytes: a longer written program (a long move at 1 um, thousands of lines) is not
/// measured: instrumented, verify takes a second or more for every 10 kB of it.
constexpr std::size_t kLongestChecked = 64 * 1024;

const model::ForwardModel& sample_forward_model() {
  static const model::ForwardModel model(sample_machine());
  return model;
}

/// The written program, in memory (closed, and so complete, when it goes).
class WrittenProgram {
 public:
  WrittenProgram() : file_(open_memstream(&data_, &size_)) {}
  WrittenProgram(const WrittenProgram&) = delete;
  WrittenProgram& operator=(const WrittenProgram&) = delete;
  ~WrittenProgram() {
    if (file_) std::fclose(file_);
    std::free(data_);
  }
  [[nodiscard]] std::FILE* file() const { return file_; }
  /// What was written, once the job is done.
  [[nodiscard]] std::string text() {
    std::fflush(file_);
    return {data_, size_};
  }

 private:
  char* data_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* file_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The input stays a plain program (any finding runs as it is with `ccomp`): its length
  // picks the dialect and the job's options, so each option meets every kind of program.
  static const std::array<const char*, 5> kDialects = {"linuxcnc", "fanuc", "mazak", "wincnc", "siemens"};
  compensate::JobOptions options;
  options.interpreter.dialect = *gcode::dialect_named(kDialects[size % kDialects.size()]);
  options.interpreter.tools = sample_tools();
  options.interpreter.max_blocks = 5'000;                                  // see gcode_fuzz.cpp
  options.sensors = {{"bed", 24.0}, {"column", 23.0}, {"spindle", 31.0}};  // the bench's readings
  options.time = 3600.0;
  options.force = true;
  const std::size_t pick = size / kDialects.size();
  options.expand_cycles = (pick & 1U) != 0;
  options.resolve_cutter_comp = (pick & 2U) != 0;
  options.flatten = (pick & 4U) != 0;
  options.decimals = (pick & 8U) != 0 ? 3 : -1;
  // (a coarser tolerance too: under the fuzzer's instrumentation the job runs ~100x slower,
  // and a fine one on a long turn of the table writes thousands of lines)
  options.tolerance = (pick & 16U) != 0 ? 0.01 : 0.001;
  options.threads = (pick & 32U) != 0 ? 2 : 1;  // the pipeline of two threads, its hand-overs
  const std::string program(reinterpret_cast<const char*>(data), size);
  std::string written;
  (void)fuzz::read_or_refuse([&] {
    WrittenProgram out;
    if (!out.file()) return;  // (no memory for the stream: nothing to run)
    gcode::LineSource source = gcode::LineSource::from_string(program, "fuzz.ngc");
    (void)compensate::run_program_job(source, out.file(), sample_machine(), options);
    written = out.text();
  });
  if (written.empty() || written.size() > kLongestChecked) return 0;  // (empty: refused)
  // What the job wrote, verify and predict must read as they are: a refusal of either
  // (ccomp::Error) is a finding here, whatever the figures they give.
  compensate::CheckOptions check;
  check.interpreter = options.interpreter;
  check.interpreter.max_blocks = 1'000'000;  // the written program's split moves are lines of their own
  check.conditions = model::conditions_for(sample_machine(), options.sensors, options.time);
  try {
    gcode::LineSource original = gcode::LineSource::from_string(program, "fuzz.ngc");
    gcode::LineSource compensated = gcode::LineSource::from_string(written, "fuzz-out.ngc");
    (void)compensate::verify(original, compensated, sample_forward_model(), check);
    gcode::LineSource again = gcode::LineSource::from_string(program, "fuzz.ngc");
    (void)compensate::predict(again, sample_forward_model(), check);
  } catch (const Error& e) {
    std::fprintf(stderr, "finding: verify or predict refused what the job wrote: %s\n", e.what());
    std::abort();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "finding: %s escaped verify or predict: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
  return 0;
}
