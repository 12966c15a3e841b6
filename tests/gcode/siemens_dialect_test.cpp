// The siemens dialect (Sinumerik 840D syntax): parentheses hold a command's arguments and
// `;` alone opens a comment; named commands, `X=10` and extended addresses are parsed with
// their spans; the interpreter follows TRAORI/TRAFOOF, ORIAXES and D as a cutting edge, and
// refuses at its column what it does not follow.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "ccomp/error.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/parser.hpp"
#include "ccomp/gcode/tool_table.hpp"

namespace ccomp::gcode {
namespace {

struct Parsed {
  std::string text;  // owns the bytes the block views
  Block block;
};

Parsed parse(const std::string& line, const char* dialect = "siemens", bool fast_path = true) {
  Parsed p{line, {}};
  Parser parser(*dialect_named(dialect), fast_path);
  parser.parse(p.text, 3, "t.mpf", p.block);
  return p;
}

/// The error a line gives: "column: message".
std::string parse_error(const std::string& line, const char* dialect = "siemens") {
  try {
    (void)parse(line, dialect);
  } catch (const Error& e) {
    return std::to_string(e.where().column) + ": " + e.message();
  }
  return "no error";
}

TEST(SiemensParser, CommandsKeepTheirNamesAndArgumentsAsWritten) {
  const Parsed p = parse("N50 cycle832(0.01, _SEMIFIN ,1) TRAORI G0 X1");
  ASSERT_EQ(p.block.commands.size(), 2U);
  EXPECT_EQ(p.block.slice(p.block.commands[0].name), "cycle832");
  EXPECT_TRUE(p.block.commands[0].has_arguments);
  EXPECT_EQ(p.block.slice(p.block.commands[0].arguments), "0.01, _SEMIFIN ,1");
  EXPECT_EQ(p.block.slice(p.block.commands[1].span), "TRAORI");
  EXPECT_FALSE(p.block.commands[1].has_arguments);
  ASSERT_EQ(p.block.words.size(), 2U);
  EXPECT_FALSE(p.block.is_empty());
  EXPECT_FALSE(parse("ORIAXES").block.is_empty()) << "a command is no O statement";
  EXPECT_FALSE(parse("ORIAXES").block.o.present);
}

TEST(SiemensParser, StringsAreVerbatimAndOnlyTheSemicolonComments) {
  const Parsed p = parse(R"x(MSG("Rough ; pass (1)") ; done (really))x");
  ASSERT_EQ(p.block.commands.size(), 1U);
  EXPECT_EQ(p.block.slice(p.block.commands[0].arguments), R"x("Rough ; pass (1)")x");
  ASSERT_EQ(p.block.comments.size(), 1U);
  EXPECT_EQ(p.block.slice(p.block.comments[0].text), " done (really)");
}

TEST(SiemensParser, AnAddressMayTakeItsValueAfterAnEqualsSign) {
  for (bool fast : {true, false}) {
    const Parsed p = parse("G1 X=-1.5 A3=0.25 F200", "siemens", fast);
    ASSERT_EQ(p.block.words.size(), 4U);
    const Word& x = p.block.words[1];
    EXPECT_EQ(x.letter, 'X');
    EXPECT_EQ(x.extension, 0U);
    EXPECT_EQ(p.block.slice(x.span), "X=-1.5");
    EXPECT_EQ(p.block.slice(x.value_span), "-1.5") << "the writer replaces the number, not the '='";
    EXPECT_DOUBLE_EQ(x.value.literal, -1.5);
    EXPECT_EQ(p.block.words[2].extension, 3U);
    EXPECT_EQ(p.block.slice(p.block.words[2].value_span), "0.25");
  }
}

TEST(SiemensParser, MalformedSyntaxIsAnErrorAtItsColumn) {
  EXPECT_EQ(parse_error(R"x(MSG("open)x"), "10: unclosed string: expected '\"' before the end of the line");
  EXPECT_EQ(parse_error("CYCLE832(0.01,1"), "16: expected ')' to close the command's arguments");
  EXPECT_EQ(parse_error("G1 X=AC(5)"), "6: expected a value after the letter: a number, [expression], #parameter or "
                                       "function");
  EXPECT_EQ(parse_error("A0=5"), "2: an extended address has 1 to 99 after its letter (A3=, C7=)");
  // Outside the dialect none of it is read.
  EXPECT_NE(parse_error("TRAORI", "linuxcnc"), "no error");
  EXPECT_NE(parse_error("G1 X=1", "fanuc"), "no error");
}

// --- the interpreter ---------------------------------------------------------------------

struct Recorded : CanonSink {
  void motion(const Motion& m) override { moves.push_back(m); }
  std::vector<Motion> moves;
};

InterpreterOptions siemens_options() {
  InterpreterOptions o;
  o.dialect = *dialect_named("siemens");
  std::istringstream table("T1 P1 Z100.0 D10.0\nT2 P2 Z80.0 D6.0\n");
  o.tools = read_tool_table(table, "t.tbl");
  o.tcp = TcpCodes::follow;
  return o;
}

struct Outcome {
  Recorded sink;
  ModalState modal;
  Offsets offsets;
};

Outcome run(const std::string& program) {
  Outcome r;
  LineSource source = LineSource::from_string(program, "t.mpf");
  Interpreter interpreter(siemens_options());
  interpreter.run(source, r.sink);
  r.modal = interpreter.modal();
  r.offsets = interpreter.offsets();
  return r;
}

/// The refusal a program gives: "exit kind line:column: message start".
std::string refusal(const std::string& program) {
  try {
    (void)run(program);
  } catch (const Error& e) {
    return fmt::format("{} {}:{}: {}", static_cast<int>(e.kind()), e.where().line, e.where().column, e.message());
  }
  return "no refusal";
}

TEST(SiemensInterpreter, TraoriIsOnUntilTrafoofAndTakesTheEdgesLength) {
  const Outcome r = run("T1 M6\nORIMKS ORIAXES\nTRAORI\nG0 X1 Z50 A5\nG1 X2 A6 F100\nTRAFOOF\nG1 X3\nM30\n");
  ASSERT_EQ(r.sink.moves.size(), 3U);
  EXPECT_TRUE(r.sink.moves[0].tcp);
  EXPECT_TRUE(r.sink.moves[1].tcp);
  EXPECT_FALSE(r.sink.moves[2].tcp);
  EXPECT_EQ(r.modal.cutting_edge, 1) << "a tool change takes edge 1";
  EXPECT_DOUBLE_EQ(r.offsets.tool[2], 100.0);
}

TEST(SiemensInterpreter, DSelectsTheEdgeOfTheToolInTheSpindle) {
  EXPECT_DOUBLE_EQ(run("T2 M6 D1\nG0 X0\nM30\n").offsets.tool[2], 80.0);
  EXPECT_DOUBLE_EQ(run("T2 M6 D0\nG0 X0\nM30\n").offsets.tool[2], 0.0);
  EXPECT_DOUBLE_EQ(run("T2 M6\nD0\nD1\nG0 X0 H5\nM30\n").offsets.tool[2], 80.0) << "H goes to the PLC";
  // A tool table holds one length and radius a tool: a second edge's are not there.
  EXPECT_TRUE(refusal("T2 M6 D2\nM30\n").starts_with(fmt::format("{} 1:7: D2", static_cast<int>(ErrorKind::unsupported))));
  // The radius of G41 is the spindle's tool's (tool 2: 3 mm), not a tool the D names: the
  // tool centre runs 3 mm left of the programmed line along X.
  const Outcome left = run("T2 M6 D1\nG0 X0 Y0\nG41 G1 X10 Y0 F100\nG1 X20\nG1 X30\nG40 G1 X40\nM30\n");
  bool three_left = false;
  for (const Motion& m : left.sink.moves) three_left = three_left || std::abs(m.end[1] - 3.0) < 1e-9;
  EXPECT_TRUE(three_left);
}

TEST(SiemensInterpreter, TheSiemensCodesOfUnitsAndDwellAreRead) {
  EXPECT_EQ(run("G700\nG0 X1\nM30\n").modal.units, Units::inch);
  EXPECT_EQ(run("G700\nG710\nG0 X1\nM30\n").modal.units, Units::mm);
  EXPECT_EQ(run("G700\nG71\nG0 X1\nM30\n").modal.units, Units::mm);
  // G4's F is its time in seconds: the feed rate stays.
  EXPECT_DOUBLE_EQ(run("G1 X1 F300\nG4 F2\nG1 X2\nM30\n").sink.moves.back().feed, 300.0);
  EXPECT_EQ(refusal("G4\nM30\n").substr(0, 2), "3 ");
  EXPECT_EQ(refusal("G4 S10\nM30\n").substr(0, 6), "3 1:4:") << "turns with no spindle speed";
  EXPECT_EQ(refusal("S600 M3\nG4 S10\nM30\n"), "no refusal");
}

TEST(SiemensInterpreter, WhatIsNotFollowedIsRefusedAtItsColumn) {
  const int unsupported = static_cast<int>(ErrorKind::unsupported);
  auto starts = [](const std::string& text, const std::string& start) { return text.rfind(start, 0) == 0; };
  const std::string disagree = refusal("T1 M6\nORIAXES\nTRAORI\nG0 X1 Z50 A5\nG1 X2 A6 F100\nM30\n");
  EXPECT_TRUE(starts(disagree, fmt::format("{} 5:7: a rotary axis turns under TRAORI: ORIWKS and ORIAXES disagree",
                                           unsupported)))
      << disagree;
  const std::string euler = refusal("TRAORI\nG1 X2 A2=0 B2=0 C2=1 F100\nM30\n");
  EXPECT_TRUE(starts(euler, fmt::format("{} 2:7: A2=: the tool's direction as Euler or RPY angles", unsupported)))
      << euler;
  const std::string swivel = refusal("G0 X0\nN20 CYCLE800(1,\"TC1\",200000,57,0,0,0,30,0,0,0,0,0,-1,100,1)\nM30\n");
  EXPECT_TRUE(starts(swivel, fmt::format("{} 2:5: CYCLE800: swivels the working plane", unsupported))) << swivel;
  const std::string frame = refusal("G0 X0\nTRANS X10\nM30\n");
  EXPECT_TRUE(starts(frame, fmt::format("{} 2:1: TRANS: a programmable frame", unsupported))) << frame;
  const std::string unknown = refusal("G0 X0\nG1 X5 FOO F100\nM30\n");
  EXPECT_TRUE(starts(unknown, fmt::format("{} 2:7: FOO: a command the siemens dialect does not read", unsupported)))
      << unknown;
  const std::string g70 = refusal("G70\nM30\n");
  EXPECT_TRUE(starts(g70, fmt::format("{} 1:1: G70 gives lengths in inches", unsupported))) << g70;
  const std::string iso = refusal("G0 X0\nG81 X1 Z-2 R1 F100\nM30\n");
  EXPECT_TRUE(starts(iso, fmt::format("{} 2:1: G81 is not Siemens syntax", unsupported))) << iso;
  const std::string g58 = refusal("G58 X10\nM30\n");
  EXPECT_TRUE(starts(g58, fmt::format("{} 1:1: G58 is a Siemens axial programmable offset", unsupported))) << g58;
  const std::string edge = refusal("T1 M6\nTRAORI\nG0 X1 A5\nD0\nM30\n");
  EXPECT_TRUE(starts(edge, fmt::format("{} 4:1: a change of the tool's length offset under TRAORI", unsupported)))
      << edge;
}

// How the tool turns under TRAORI is what the program's codes settle whichever G group the
// control's machine data make decide: ORIWKS with ORIVECT (the basic settings) a great
// circle, ORIMKS with ORIAXES the rotary axes linearly; a pair that disagrees, a cone or a
// curve is refused where a rotary axis turns (a turn too small to tell them apart is not).
TEST(SiemensInterpreter, TheOrientationInterpolationIsTheOneBothGroupsSay) {
  const std::string moves = "G0 X1 Z50 A5 C0\nG1 X2 A6 C10 F100\nM30\n";
  const Outcome basic = run("T1 M6\nTRAORI\n" + moves);
  ASSERT_EQ(basic.sink.moves.size(), 2U);
  EXPECT_TRUE(basic.sink.moves[1].tcp_great_circle);
  const Outcome axes = run("T1 M6\nORIMKS ORIAXES TRAORI\n" + moves);
  EXPECT_FALSE(axes.sink.moves[1].tcp_great_circle);
  const int unsupported = static_cast<int>(ErrorKind::unsupported);
  EXPECT_TRUE(refusal("T1 M6\nORIMKS TRAORI\n" + moves)
                  .starts_with(fmt::format("{} 4:7: a rotary axis turns under TRAORI: ORIMKS and ORIVECT disagree",
                                           unsupported)));
  EXPECT_TRUE(refusal("T1 M6\nORICONCW TRAORI\n" + moves)
                  .starts_with(fmt::format("{} 4:7: a rotary axis turns under TRAORI: the tool's direction goes along a "
                                           "cone",
                                           unsupported)));
  EXPECT_EQ(refusal("T1 M6\nORIAXES TRAORI\nG0 X1 Z50 A5\nG1 X2 A5.005 F100\nM30\n"), "no refusal");
  // An arc whose rotary axes turn: followed where they move linearly, not on a great circle.
  const std::string arc = "G0 X10 Y0 Z50 A5\nG3 X-10 Y0 I-10 J0 A10 F100\nM30\n";
  EXPECT_EQ(refusal("T1 M6\nORIMKS ORIAXES TRAORI\n" + arc), "no refusal");
  EXPECT_TRUE(refusal("T1 M6\nTRAORI\n" + arc)
                  .starts_with(fmt::format("{} 4:20: a rotary axis turns under TRAORI: an arc", unsupported)));
  EXPECT_EQ(refusal("T1 M6\nTRAORI\nG0 X10 Y0 Z50 A5\nG3 X-10 Y0 I-10 J0 F100\nM30\n"), "no refusal");
}

TEST(SiemensInterpreter, OtherTransformationsAndCommentsInParenthesesAreNotRead) {
  const int unsupported = static_cast<int>(ErrorKind::unsupported);
  EXPECT_EQ(refusal("TRAORI(1)\nM30\n"), "no refusal");
  EXPECT_TRUE(refusal("TRAORI(2)\nM30\n").starts_with(fmt::format("{} 1:8: TRAORI with arguments", unsupported)));
  EXPECT_EQ(refusal("G1 X10 F100 (a comment)\nM30\n").substr(0, 7), "3 1:13:");
  EXPECT_EQ(refusal("TRANSMIT\nM30\n").find("a kinematic transformation other than TRAORI") != std::string::npos, true);
  EXPECT_EQ(refusal("SPOS=90 CYCLE832(0.01,(1),1)\nM30\n"), "no refusal");
  EXPECT_TRUE(refusal("G505\nM30\n").starts_with(fmt::format("{} 1:1: G505: a settable work offset", unsupported)));
  EXPECT_TRUE(refusal("G74 X0\nM30\n").starts_with(fmt::format("{} 1:1: G74 approaches", unsupported)));
}

// A3= B3= C3= under TRAORI: the direction (a component left out 0) goes to the caller's
// kinematics, the move ends at their angles and says the program gives directions, until a
// block gives angles again; outside TRAORI, or beside angle words, they are refused.
TEST(SiemensInterpreter, ADirectionVectorTakesItsAnglesFromTheCaller) {
  InterpreterOptions o = siemens_options();
  std::vector<std::array<double, 3>> asked;
  o.tcp_direction = [&asked](const std::array<double, 3>& d, const Axes& p, const Offsets&) -> std::optional<Axes> {
    asked.push_back(d);
    Axes q = p;
    q[3] = 100 * d[0], q[5] = 100 * d[1];
    return q;
  };
  Recorded sink;
  LineSource source = LineSource::from_string(
      "T1 M6\nTRAORI\nG0 X1 Z50 A3=0.5 C3=0.8\nG1 X2 B3=0.25 C3=1 F100\nC3=1\nG1 X3 A7 C9\nTRAFOOF\nM30\n", "t.mpf");
  Interpreter(o).run(source, sink);
  EXPECT_EQ(asked, (std::vector<std::array<double, 3>>{{0.5, 0, 0.8}, {0, 0.25, 1}, {0, 0, 1}}));
  ASSERT_EQ(sink.moves.size(), 4U);
  EXPECT_DOUBLE_EQ(sink.moves[0].end[3], 50.0);
  EXPECT_DOUBLE_EQ(sink.moves[1].end[5], 25.0);
  EXPECT_DOUBLE_EQ(sink.moves[2].end[5], 0.0) << "a direction alone is a move";
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(sink.moves[k].direction_words, DirectionWords::siemens_vector) << k;
    EXPECT_TRUE(sink.moves[k].tcp_great_circle) << k;
  }
  EXPECT_EQ(sink.moves[3].direction_words, DirectionWords::none) << "angles again";
  for (const char* program : {"G1 X1 A3=0 B3=0 C3=1 F100\nM30\n", "TRAORI\nG1 X1 A5 C3=1 F100\nM30\n"}) {
    LineSource refused = LineSource::from_string(program, "t.mpf");
    Recorded ignored;
    try {
      Interpreter(o).run(refused, ignored);
      FAIL() << program;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::unsupported) << e.message();
    }
  }
}

// A blank between a word's letter and its number reads the same whichever path reads the line.
TEST(SiemensParser, TheFastPathAndTheGrammarReadBlanksAlike) {
  for (const char* line : {"G1 X 10 F100", "G1 X 10 F100 ORIAXES", "N10 G1 X 10", "N 10 M 3 X 10 ORIAXES"}) {
    const Parsed p = parse(line);
    const auto x = std::find_if(p.block.words.begin(), p.block.words.end(), [](const Word& w) { return w.letter == 'X'; });
    ASSERT_NE(x, p.block.words.end()) << line;
    EXPECT_DOUBLE_EQ(x->value.literal, 10.0) << line;
  }
}

}  // namespace
}  // namespace ccomp::gcode
