// The check's HTML report: one self-contained page (nothing fetched from a network) whose
// plots headless Chromium renders: every chart is in the rendered DOM with its points, and
// the screenshot is not blank.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(HtmlReport, IsSelfContainedAndRendersInChromium) {
  const std::string dir = temp_dir("html_report");
  const std::string csv = dir + "/meas.csv", html = dir + "/report.html";
  CommandResult r = run_command(shell_quote(ccomp_binary()) + " simulate -m " +
                                shell_quote(source_dir() + "/samples/measurements/hmc-truth.yaml") +
                                " --plan nine_lines --plan sphere --step 10 -o " + shell_quote(csv));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_command(shell_quote(ccomp_binary()) + " check " + shell_quote(csv) + " -m " +
                  shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml") + " --report " +
                  shell_quote(html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = read_file(html);
  // Self-contained: no scripts, no fetched resources (the SVG namespace is a name, not a fetch).
  EXPECT_EQ(count(page, "<script"), 0U);
  EXPECT_EQ(count(page, "src="), 0U);
  EXPECT_EQ(count(page, "href="), 0U);
  EXPECT_EQ(count(page, "url("), 0U);
  const std::size_t charts = count(page, "<svg class=\"chart\"");
  EXPECT_GE(charts, 10U) << "residual against x y z b, three maps, three spectra, singular values";
  EXPECT_NE(page.find("Missing effects"), std::string::npos);
  EXPECT_NE(page.find("reversal of the Y axis"), std::string::npos) << "the truth's backlash is named";
  // Each suggestion has its chart: what is left with it added.
  const auto added = page.find("Each missing effect, added");
  ASSERT_NE(added, std::string::npos);
  EXPECT_GE(count(page.substr(added), "<svg class=\"chart\""), 1U);
  EXPECT_NE(page.find("1: EYY reversal"), std::string::npos);
  EXPECT_NE(page.find("Identifiability"), std::string::npos);

  const std::string chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    GTEST_SKIP() << "Debian's chromium is not installed (tools/install-deps.sh installs it)";
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync --user-data-dir=" +
      shell_quote(dir + "/profile") + " ";
  r = run_command("timeout 120 " + chromium + flags + "--dump-dom " + shell_quote("file://" + html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count(r.out, "<svg class=\"chart\""), charts) << "every chart is in the rendered page";
  EXPECT_GT(count(r.out, "<circle"), 1000U);
  EXPECT_GT(count(r.out, "<polyline"), 2U);
  r = run_command("timeout 120 " + chromium + flags + "--window-size=1200,2400 --screenshot=" +
                  shell_quote(dir + "/report.png") + " " + shell_quote("file://" + html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // A blank page compresses to a few kB; hundreds of plotted points do not.
  EXPECT_GT(std::filesystem::file_size(dir + "/report.png"), 50000U);
}

}  // namespace
}  // namespace ccomp::test
