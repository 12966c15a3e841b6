#include "linuxcnc_suite.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "trace_capture.hpp"

namespace ccomp::test {

namespace fs = std::filesystem;

std::ostream& operator<<(std::ostream& os, const SuiteCase& c) {
  return os << c.name;
}

// LinuxCNC's expected output for G84 in G18/G19 puts the tapping depth on the wrong axis
// (the feed's coordinates come out permuted, unlike G81 in the same planes): a LinuxCNC bug
// that ccomp does not copy. interpreter_test.cpp checks ccomp's G84 in G18/G19 instead.
constexpr const char* kG84Permuted =
    "LinuxCNC permutes the G84 feed coordinates outside G17; ccomp taps along the plane normal";

const std::vector<SuiteCase>& suite_cases() {
  static const std::vector<SuiteCase> cases = {
      // tests/ccomp: cutter radius compensation, the offset path as rs274 computes it.
      {"ccomp_mill_g90g91g92", "ccomp/mill-g90g91g92/test.ngc", Expect::same_motions, "", "test.tbl"},
      {"ccomp_mill_zchanges", "ccomp/mill-zchanges/test.ngc", Expect::same_motions, "", "test.tbl"},
      {"ccomp_lathe_comp", "ccomp/lathe-comp/test.ngc", Expect::out_of_scope, "", "", "", "",
       "lathe (G7/G18 diameter mode with cutter compensation)"},
      {"crazy_paths", "interp/crazy-paths/test.ngc", Expect::same_motions},
      {"inside_corners", "interp/inside-corners/test.ngc", Expect::same_motions},
      {"exists", "interp/exists/test.ngc", Expect::same_motions},
      {"flowsnake", "interp/flowsnake/flowsnake.ngc", Expect::same_motions},
      {"g10_l1_l10", "interp/g10/g10-l1-l10/test.ngc", Expect::same_motions, "", "test.tbl"},
      {"g10_l11", "interp/g10/g10-l11/test.ngc", Expect::same_motions, "", "test.tbl"},
      {"g10_l20_while_active", "interp/g10/g10-l20-while-active/test.ngc", Expect::same_motions},
      {"g10_with_g92", "interp/g10/g10-with-g92/test.ngc", Expect::same_motions, "", "test.tbl"},
      {"g52_g92_interaction", "interp/g52/g52-g92-interaction/g52-g92-interaction.ngc", Expect::same_motions, "", "",
       "", "", "", false},
      {"g92_offset_persistence", "interp/g52/g92-offset-persistence/g92_offsets.ngc", Expect::out_of_scope, "", "", "",
       "", "G92 persistence through LinuxCNC's .var file between runs is the controller's"},
      {"g64_r_planner", "interp/g64-r-planner/test.ngc", Expect::accepted},
      {"g71_endless_loop", "interp/g71-endless-loop/g71-endless-loop.ngc", Expect::out_of_scope, "", "", "", "",
       "lathe roughing cycle G71"},
      {"g71_endless_loop_2", "interp/g71-endless-loop_2/g71-endless-loop_2.ngc", Expect::out_of_scope, "", "", "", "",
       "lathe roughing cycle G71"},
      {"g71_with_g70", "interp/g71-with-g70/g71-with-g70.ngc", Expect::out_of_scope, "", "", "", "",
       "lathe cycles G70/G71"},
      {"g72_missing_iteration", "interp/g72-missing-iteration/g72-iterations-missing.ngc", Expect::out_of_scope, "", "",
       "", "", "lathe cycle G72"},
      {"g76", "interp/g76/g76only.ngc", Expect::out_of_scope, "", "", "", "", "lathe threading cycle G76"},
      {"g81_g17_g99", "interp/g81/g17/g99/g17-g99-g81.ngc", Expect::same_motions},
      {"g81_g18_g98", "interp/g81/g18/g98/g18-g98-g81.ngc", Expect::same_motions},
      {"g81_g19_g98", "interp/g81/g19/g98/g19-g98-g81.ngc", Expect::same_motions},
      {"g81_g19_g99", "interp/g81/g19/g99/g19-g99-g81.ngc", Expect::same_motions},
      {"g84_g17_g99", "interp/g84/g17/g99/g17-g99-g84.ngc", Expect::same_motions},
      {"g84_g18_g98", "interp/g84/g18/g98/g18-g98-g84.ngc", Expect::out_of_scope, "", "", "", "", kG84Permuted},
      {"g84_g19_g98", "interp/g84/g19/g98/g19-g98-g84.ngc", Expect::out_of_scope, "", "", "", "", kG84Permuted},
      {"g84_g19_g99", "interp/g84/g19/g99/g19-g99-g84.ngc", Expect::out_of_scope, "", "", "", "", kG84Permuted},
      {"iniparam_failassign", "interp/iniparam-failassign/test.ngc", Expect::rejected},
      {"abort_hot_comment", "interp/abort-hot-comment/test.ngc", Expect::rejected, "", "", "", "_ini[a]value=3.14"},
      {"m19", "interp/m19/test.ngc", Expect::accepted},
      {"m98m99_basics", "interp/m98m99/01-basics/test.ngc", Expect::same_motions},
      {"m98m99_no_p_word", "interp/m98m99/03-error-M98-no-P-word/test.ngc", Expect::rejected},
      {"m98m99_no_sub", "interp/m98m99/04-M98-but-no-sub/test.ngc", Expect::rejected},
      {"m98m99_o_called_with_o_call", "interp/m98m99/06-error-mixed-sub-styles/O...-called-with-O..._call.ngc",
       Expect::rejected},
      {"m98m99_o_ended_with_endsub", "interp/m98m99/06-error-mixed-sub-styles/O...-ended-with-O..._endsub.ngc",
       Expect::rejected},
      {"m98m99_sub_called_with_m98", "interp/m98m99/06-error-mixed-sub-styles/O...-sub-called-with-M98.ngc",
       Expect::rejected},
      {"m98m99_sub_ended_with_m99", "interp/m98m99/06-error-mixed-sub-styles/O...-sub-ended-with-M99.ngc",
       Expect::rejected},
      {"m98m99_nested_subs", "interp/m98m99/07-nested-subs/test.ngc", Expect::same_motions},
      {"m98m99_disable_fanuc_subs", "interp/m98m99/09-disable-fanuc-subs/test-fanuc.ngc", Expect::out_of_scope, "", "",
       "", "", "tests LinuxCNC's DISABLE_FANUC_STYLE_SUB INI switch; ccomp always reads Fanuc subprograms"},
      {"m98m99_p001", "interp/m98m99/10-M98-P001/test.ngc", Expect::same_motions},
      {"m98m99_endless_main", "interp/m98m99/12-M99-endless-main-program/test.ngc", Expect::out_of_scope, "", "", "",
       "", "M99 in a main program restarts it for ever on a controller; ccomp ends there (and warns)"},
      {"m98m99_named_program", "interp/m98m99/13-named-program/test-named.ngc", Expect::accepted},
      {"m98m99_numbered_program", "interp/m98m99/13-named-program/test-numbered.ngc", Expect::accepted},
      {"machine_coord_params", "interp/machine-coord-params/test.ngc", Expect::same_messages, "", "test.tbl"},
      {"magic_comments", "interp/magic_comments/param_format_printing/test.ngc", Expect::out_of_scope, "", "", "", "",
       "printf formats in DEBUG comments only change messages, not motion"},
      {"nested_sub_error", "interp/nested-sub-error/test.ngc", Expect::rejected, "", "", "subs"},
      {"nested_sub_in_file_error", "interp/nested-sub-in-file-error/test.ngc", Expect::rejected, "", "", "subs"},
      {"sub_call_from_sub", "interp/sub-call-from-sub/test.ngc", Expect::same_motions, "", "", "subs"},
      {"oword_bug315_p2", "interp/oword-bug315-p2/test.ngc", Expect::same_motions},
      {"oword_unwind", "interp/oword-unwind/test.ngc", Expect::out_of_scope, "", "", "", "",
       "tests how rs274's interactive mode carries on after an error; ccomp stops at the first error"},
      {"return_value", "interp/return-value/test.ngc", Expect::same_motions},
      {"subs_follow_main", "interp/subs-follow-main/test.ngc", Expect::same_motions},
      {"rotation_g28", "interp/rotation/g28/g28.ngc", Expect::same_motions},
      {"rotation_g53", "interp/rotation/g53/g53.ngc", Expect::same_motions},
      {"plug_filename", "interp/plug/filename/test.sh", Expect::out_of_scope, "", "", "", "",
       "loads an interpreter plug-in (canterp.so)"},
      {"plug_relative", "interp/plug/relative/test.sh", Expect::out_of_scope, "", "", "", "",
       "loads an interpreter plug-in (canterp.so)"},
      {"python_self", "interp/python-self/test.ngc", Expect::out_of_scope, "", "", "", "", "Python O-word subroutines"},
      {"value_returned", "interp/value-returned/test.ngc", Expect::out_of_scope, "", "", "", "",
       "Python O-word subroutines"},
      {"compile", "interp/compile/use-rs274.cc", Expect::out_of_scope, "", "", "", "",
       "compiles a C++ program against LinuxCNC's interpreter library"},
  };
  return cases;
}

const SuiteCase* suite_case(std::string_view program) {
  for (const SuiteCase& c : suite_cases())
    if (program == c.program) return &c;
  return nullptr;
}

std::ostream& operator<<(std::ostream& os, const SuiteProgram& p) {
  return os << p.path;
}

std::vector<SuiteProgram> suite_programs() {
  std::vector<SuiteProgram> programs;
  const fs::path root = fs::path(corpus_dir()) / "linuxcnc";
  if (!fs::exists(root)) return programs;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file() && e.path().extension() == ".ngc" && e.path().string().find("/bad/") == std::string::npos)
      programs.push_back({fs::relative(e.path(), root).string()});
  std::sort(programs.begin(), programs.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  return programs;
}

std::string suite_test_name(const ::testing::TestParamInfo<SuiteProgram>& program) {
  std::string name = program.param.path;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

// The listing the parametrised suites are made of: were the corpus not found, they would
// have no cases and nothing to fail.
TEST(LinuxcncSuite, ListsTheCorpusProgramsButNotTheBadOnes) {
  const std::vector<SuiteProgram> programs = suite_programs();
  EXPECT_GE(programs.size(), 60U) << "corpus at " << corpus_dir();
  for (const SuiteProgram& p : programs) EXPECT_EQ(p.path.find("bad/"), std::string::npos) << p.path;
}

}  // namespace ccomp::test
