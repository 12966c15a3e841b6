// Throughput of the front end in memory: tokenising (lexer + parser into the lossless
// block model) and parse + interpret, on LinuxCNC's stellabee1.ngc (169,220 lines).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/parser.hpp"

namespace {

const std::string& program() {
  static const std::string text = [] {
    const char* path = CCOMP_CORPUS_DIR "/programs/stellabee1.ngc";
    std::ifstream in(path, std::ios::binary);
    if (!in) {  // an empty program would benchmark nothing and still print figures
      std::fprintf(stderr, "ccomp_bench_frontend: cannot read %s\n", path);
      std::exit(2);
    }
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }();
  return text;
}

std::vector<std::string_view> lines() {
  std::vector<std::string_view> out;
  std::string_view all = program();
  for (std::size_t at = 0; at < all.size();) {
    const std::size_t nl = all.find('\n', at);
    const std::size_t end = nl == std::string_view::npos ? all.size() : nl;
    out.push_back(all.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

void Tokenise(benchmark::State& state) {
  const auto all = lines();
  ccomp::gcode::Parser parser;
  ccomp::gcode::Block block;
  for (auto _ : state) {
    std::uint32_t n = 0;
    for (std::string_view l : all) parser.parse(l, ++n, "stellabee1.ngc", block);
    benchmark::DoNotOptimize(block.words.size());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * program().size()));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * all.size()));
}
BENCHMARK(Tokenise)->Unit(benchmark::kMillisecond);

class CountingSink : public ccomp::gcode::CanonSink {
 public:
  void motion(const ccomp::gcode::Motion& /*m*/) override { ++motions; }
  std::size_t motions = 0;
};

void ParseAndInterpret(benchmark::State& state) {
  const std::size_t line_count = lines().size();
  for (auto _ : state) {
    auto source = ccomp::gcode::LineSource::from_string(program(), "stellabee1.ngc");
    CountingSink sink;
    ccomp::gcode::Interpreter interpreter;
    interpreter.run(source, sink);
    benchmark::DoNotOptimize(sink.motions);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * program().size()));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * line_count));
}
BENCHMARK(ParseAndInterpret)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
