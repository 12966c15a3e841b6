// libFuzzer target: G-code programs, parsed and interpreted block by block as the main job
// does (gcode::Interpreter, with a tool table of three tools, tool centre point codes
// followed), without writing anything. Arcs are
// taken apart into points as the job does before it compensates their chords.
#include <array>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/dialect.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/source.hpp"
#include "ccomp/gcode/tool_table.hpp"
#include "fuzz_outcome.hpp"

namespace {

using namespace ccomp::gcode;

class ArcPoints : public CanonSink {
 public:
  void motion(const Motion& m) override {
    if (m.kind != MotionKind::arc) return;
    const ArcGeometry g = arc_geometry(m);
    for (double f : {0.0, 0.5, 1.0}) (void)arc_point(m, g, f);
  }
};

const ToolTable& sample_tools() {
  static const ToolTable tools = [] {
    std::istringstream in("T1 P1 Z100.0 D10.0\nT2 P2 Z120.0 D6.0\nT3 P3 Z90.0 D8.0 X0.5\n");
    return read_tool_table(in, "fuzz.tbl");
  }();
  return tools;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The input stays a plain program (any corpus file runs as it is with `ccomp trace`): its
  // length picks the dialect, so every dialect sees every kind of program.
  static const std::array<const char*, 5> kDialects = {"linuxcnc", "fanuc", "mazak", "wincnc", "siemens"};
  InterpreterOptions options;
  options.dialect = *dialect_named(kDialects[size % kDialects.size()]);
  options.tools = sample_tools();
  // An endless loop is refused by this guard. Its default (2e9 blocks) would take hours
  // here: a block costs ~50 us under the fuzzer's instrumentation, and an input of 4 kB has
  // a few hundred lines, so 5000 blocks still runs every loop of the seeds to its end.
  options.max_blocks = 5'000;
  // Tool centre point codes followed, as the main job takes them (their modal state and
  // their refusals run too).
  options.tcp = TcpCodes::follow;
  return ccomp::fuzz::read_or_refuse([&] {
    LineSource source = LineSource::from_string(std::string(reinterpret_cast<const char*>(data), size), "fuzz.ngc");
    ArcPoints sink;
    Interpreter(options).run(source, sink);
  });
}
