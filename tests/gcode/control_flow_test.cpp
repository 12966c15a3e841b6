// O-word control flow and Fanuc subprograms: the interpreter seeks in the source, so loops
// and forward calls work while reading a file in constant memory.
#include <gtest/gtest.h>

#include <filesystem>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

std::vector<double> xs(const RunResult& r) {
  std::vector<double> out;
  for (const auto& m : r.motions) out.push_back(m.motion.end[0]);
  return out;
}

RunResult ok(const std::string& program, const gcode::InterpreterOptions& o = {}) {
  RunResult r = run_program(program, o);
  EXPECT_FALSE(r.error) << (r.error ? format_error(*r.error) : "");
  return r;
}

TEST(ControlFlow, IfElseifElse) {
  const std::string program = "o1 if [#1 EQ 1]\nG0 X1\no1 elseif [#1 EQ 2]\nG0 X2\no1 else\nG0 X3\no1 endif\nM2\n";
  for (int v : {1, 2, 7}) {
    const RunResult r = ok("#1=" + std::to_string(v) + "\n" + program);
    EXPECT_EQ(xs(r), std::vector<double>{static_cast<double>(v == 7 ? 3 : v)}) << v;
  }
}

TEST(ControlFlow, WhileDoRepeatBreakContinue) {
  EXPECT_EQ(xs(ok("#1=0\no1 while [#1 LT 3]\nG0 X#1\n#1=[#1+1]\no1 endwhile\nM2\n")), (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(xs(ok("#1=5\no1 do\nG0 X#1\n#1=[#1+1]\no1 while [#1 LT 3]\nM2\n")), (std::vector<double>{5}));
  EXPECT_EQ(xs(ok("#1=0\no1 repeat [4]\n#1=[#1+1]\nG0 X#1\no1 endrepeat\nM2\n")), (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(xs(ok("#1=0\no1 while [1]\n#1=[#1+1]\no2 if [#1 EQ 2]\no1 continue\no2 endif\n"
                  "o3 if [#1 GT 4]\no1 break\no3 endif\nG0 X#1\no1 endwhile\nG0 X9\nM2\n")),
            (std::vector<double>{1, 3, 4, 9}));
}

TEST(ControlFlow, SubroutinesDefinedAfterTheCallAndReturnValues) {
  const RunResult r =
      ok("o<twice> call [3]\nG0 X#<_value>\nM2\no<twice> sub\nG0 X#1\no<twice> return [#1*2]\n"
         "o<twice> endsub\n");
  EXPECT_EQ(xs(r), (std::vector<double>{3, 6}));
}

TEST(ControlFlow, RecursiveCallsUnwindParameters) {
  const RunResult r =
      ok("o<down> sub\no1 if [#1 GT 0]\nG0 X#1\no<down> call [#1-1]\nG0 X#1\no1 endif\n"
         "o<down> endsub\no<down> call [2]\nM2\n");
  EXPECT_EQ(xs(r), (std::vector<double>{2, 1, 1, 2}));
}

TEST(ControlFlow, FanucSubprogramsWithRepeats) {
  const RunResult r = ok("%\nO0100 (main)\nG91\nM98 P200 L3\nG90 G0 X0\nM30\nO200\nG0 X1\nM99\n%\n");
  EXPECT_EQ(xs(r), (std::vector<double>{1, 2, 3, 0}));
}

TEST(ControlFlow, Refusals) {
  auto message = [](const std::string& program) {
    const RunResult r = run_program(program);
    EXPECT_TRUE(r.error) << program;
    return r.error ? r.error->message() : std::string();
  };
  EXPECT_NE(message("o1 call\nM2\n").find("unknown subroutine O1"), std::string::npos);
  EXPECT_NE(message("M98 P7\nM2\n").find("O7"), std::string::npos);
  EXPECT_NE(message("o1 sub\no2 sub\no2 endsub\no1 endsub\nM2\n").find("nested"), std::string::npos);
  EXPECT_NE(message("o1 endwhile\nM2\n").find("without a matching while"), std::string::npos);
  EXPECT_NE(message("o1 if [1]\nG0 X1\n").find(""), std::string::npos);
  gcode::InterpreterOptions o;
  o.max_blocks = 1000;
  const RunResult endless = run_program("o1 while [1]\nG0 X1\no1 endwhile\nM2\n", o);
  ASSERT_TRUE(endless.error);
  EXPECT_NE(endless.error->message().find("endless loop"), std::string::npos);
}

TEST(ControlFlow, SubroutinesFromTheSearchPath) {
  const std::string dir = temp_dir("subpath");
  write_file(dir + "/side.ngc", "o<side> sub\nG0 X#1\no<side> endsub\nM2\n");
  gcode::InterpreterOptions o;
  o.subroutine_path = {dir};
  EXPECT_EQ(xs(ok("o<side> call [4]\nG0 X1\nM2\n", o)), (std::vector<double>{4, 1}));
}

TEST(ControlFlow, LongLoopsRunInConstantMemoryOverAFile) {
  // A loop seeks back in the file, so it works on a file source, not only in memory.
  const std::string dir = temp_dir("loopfile");
  write_file(dir + "/loop.ngc", "#1=0\no1 while [#1 LT 1000]\nG0 X#1\n#1=[#1+1]\no1 endwhile\nM2\n");
  const TraceResult t = trace_file(dir + "/loop.ngc");
  ASSERT_FALSE(t.error);
  EXPECT_EQ(motion_calls(t.lines).size(), 1000U);
}

}  // namespace
}  // namespace ccomp::test
