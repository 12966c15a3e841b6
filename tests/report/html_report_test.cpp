// The check's HTML report (docs/report.md): one self-contained page (no network reference,
// a policy that forbids any fetch) whose plotly figures headless Chromium renders: every
// plot div drawn with its traces and tick labels, every reading of a line on its plot, the
// spectrum from the Nyquist limit up, parameters in the file's units, the provenance naming
// the files by SHA-256; the screenshot not blank. And `fit --report`: the same page for the
// fitted model.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "ccomp/util/sha256.hpp"
#include "ccomp/version.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

/// The page without its script elements' text (plotly.js names map-tile servers it never
/// fetches here): what remains are the elements a browser would load from.
std::string without_scripts(const std::string& page) {
  std::string out;
  std::size_t at = 0;
  for (;;) {
    const std::size_t open = page.find("<script", at);
    if (open == std::string::npos) break;
    const std::size_t close = page.find("</script>", open);
    out += page.substr(at, open - at);
    out += page.substr(open, page.find('>', open) - open + 1);  // the tag itself: a src= shows
    if (close == std::string::npos) return out;
    at = close + 9;
  }
  return out + page.substr(at);
}

/// Each plot div of a rendered page and what Chromium drew in it, up to its figure's end.
std::vector<std::pair<std::string, std::string>> plots(const std::string& dom) {
  std::vector<std::pair<std::string, std::string>> out;
  const std::regex div(R"re(<div id="(fig-[a-z]+-\d+)")re");
  for (auto it = std::sregex_iterator(dom.begin(), dom.end(), div); it != std::sregex_iterator(); ++it) {
    const auto start = static_cast<std::size_t>(it->position());
    const std::size_t end = dom.find("</figure>", start);
    out.emplace_back((*it)[1], dom.substr(start, end == std::string::npos ? std::string::npos : end - start));
  }
  return out;
}

std::string chromium_flags(const std::string& profile) {
  return " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking "
         "--disable-component-update --disable-sync --user-data-dir=" +
         shell_quote(profile) + " --virtual-time-budget=30000 ";
}

struct Simulated {
  std::string dir, csv;
};

/// Laser lines (out and back twice, for ISO 230-2's spread), a grid and spheres, from the
/// truth of the sample data: the geometric model lacks the truth's backlash and screw error.
const Simulated& simulated() {
  static const Simulated s = [] {
    Simulated out{temp_dir("html_report"), ""};
    out.csv = out.dir + "/meas.csv";
    const CommandResult r =
        run_command(shell_quote(ccomp_binary()) + " simulate -m " +
                    shell_quote(source_dir() + "/samples/measurements/hmc-truth.yaml") +
                    " --plan nine_lines --plan grid --plan sphere --step 10 --runs 2 -o " + shell_quote(out.csv));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }();
  return s;
}

const std::string kModel = "/samples/machines/hmc-xyzb-geometric.yaml";

TEST(HtmlReport, IsSelfContainedAndRendersInChromium) {
  const Simulated& data = simulated();
  const std::string html = data.dir + "/report.html";
  CommandResult r = run_command(shell_quote(ccomp_binary()) + " check " + shell_quote(data.csv) + " -m " +
                                shell_quote(source_dir() + kModel) + " --report " + shell_quote(html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = read_file(html);

  // Offline: nothing outside the inline scripts refers to a network, and the page's policy
  // refuses any fetch whatever a script would try.
  const std::string markup = without_scripts(page);
  EXPECT_FALSE(std::regex_search(markup, std::regex(R"re((src|href)\s*=\s*"?(https?:)?//)re", std::regex::icase)));
  EXPECT_EQ(count(markup, "<script src"), 0U);
  EXPECT_EQ(count(markup, "<link"), 0U);
  EXPECT_NE(page.find("Content-Security-Policy\" content=\"default-src 'none'"), std::string::npos);
  EXPECT_GT(page.size(), 1000000U) << "plotly.js is inlined";

  // The physics the data hold: the truth's backlash is named as missing.
  EXPECT_NE(page.find("reversal of the Y axis"), std::string::npos);
  // Each missing effect on a Y line: the residual before and after adding it.
  EXPECT_NE(page.find("{\"text\":\"1. EYY reversal on y-line"), std::string::npos);
  // ISO 230-2 with the two runs the simulation made: its bands are drawn.
  EXPECT_NE(page.find("mean &plusmn; 2s of 2 runs up, 2 down"), std::string::npos);
  // The simulation's file states neither its instrument nor its temperatures: said so.
  EXPECT_NE(page.find("The test as its files state it: instrument <em>not stated</em>; temperatures <em>not "
                      "stated</em>"),
            std::string::npos);
  // Parameters in the model file's units, as fit prints them: EXX's slope is 0.012 um/mm in
  // the file (1.2e-05 in mm/mm).
  EXPECT_TRUE(std::regex_search(page, std::regex(R"re(<td>EXX\.a1</td><td>µm/mm</td><td class="num">0\.012</td>)re")))
      << "EXX.a1 as the file writes it";
  EXPECT_TRUE(std::regex_search(page, std::regex(R"re(<td>EC0X</td><td>µrad</td><td class="num">25</td>)re")));
  // Provenance: this version, the model and the measurements named by their SHA-256.
  EXPECT_NE(page.find(std::string("ccomp ") + kVersion), std::string::npos);
  EXPECT_NE(page.find(util::sha256_hex(read_file(source_dir() + kModel))), std::string::npos);
  EXPECT_NE(page.find(util::sha256_hex(read_file(data.csv))), std::string::npos);
  // The spectra start at the Nyquist limit of the lines' median step: ISO 230-2's irregular
  // targets about a 10 mm step (simulate's) put it between 2 x 5 mm and 2 x 10 mm.
  const std::regex spectrum_x(R"re("name":"amplitude","x":\[([^\]]*)\])re");
  std::size_t spectra = 0;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), spectrum_x); it != std::sregex_iterator(); ++it) {
    ++spectra;
    std::stringstream periods((*it)[1].str());
    double shortest = INFINITY;
    for (std::string p; std::getline(periods, p, ',');) shortest = std::min(shortest, std::stod(p));
    EXPECT_GE(shortest, 10.0);
    EXPECT_LT(shortest, 20.0 * 1.01) << "and reach it";
  }
  EXPECT_EQ(spectra, 3U) << "one per linear axis with laser lines";

  const std::string chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    // The page's rendering is what this checks: without the browser it fails, not passes.
    GTEST_FAIL() << "Debian's chromium is not installed at " << chromium << " (tools/install-deps.sh installs it)";
  const auto started = std::chrono::steady_clock::now();
  r = run_command("timeout 120 " + chromium + chromium_flags(temp_dir("html_report_profile")) +
                  "--enable-logging=stderr --v=0 --window-size=1280,2400 --dump-dom " + shell_quote("file://" + html));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  RecordProperty("render_seconds", std::to_string(seconds));
  // The page's console: a fetch the policy refused, or a script error, would be logged.
  EXPECT_EQ(count(r.err, "Content Security Policy"), 0U) << r.err;
  EXPECT_EQ(count(r.err, "Uncaught"), 0U) << r.err;
  const std::string& dom = r.out;
  const auto drawn = plots(dom);
  const std::size_t divs = count(page, "class=\"plot\"");
  ASSERT_EQ(drawn.size(), divs);
  EXPECT_NE(dom.find("data-plots-drawn=\"" + std::to_string(divs) + "\""), std::string::npos)
      << "the drawing script ran to its end";
  // Each line and grid on its own plots, one per direction it reads (from the CSV's n
  // columns); the spheres on polar plots; maps before and after for three planes.
  std::map<std::string, std::set<std::string>> directions;
  {
    std::ifstream csv(data.csv);
    std::string line;
    std::getline(csv, line);
    EXPECT_TRUE(line.starts_with("# frame: program G54")) << "simulate says the frame: " << line;
    std::getline(csv, line);  // the header
    while (std::getline(csv, line)) {
      std::vector<std::string> field;
      std::stringstream row(line);
      for (std::string f; std::getline(row, f, ',');) field.push_back(f);
      // x,y,z,b,L,t,vx,vy,vz,vb,nx,ny,nz,d,source
      ASSERT_EQ(field.size(), 15U) << line;
      const auto axis = [&](int k) { return std::abs(std::stod(field[static_cast<std::size_t>(10 + k)])) > 0.5; };
      directions[field[14]].insert(axis(0) ? "X" : axis(1) ? "Y" : "Z");
    }
  }
  ASSERT_GE(directions.size(), 13U) << "9 lines, 3 grids, the spheres";
  for (const auto& [source, read] : directions) {
    const std::size_t titled = count(page, "{\"text\":\"" + source + ": ");
    if (source == "sphere")
      EXPECT_GE(titled, 1U) << source;
    else
      EXPECT_EQ(titled, read.size()) << source;
  }
  EXPECT_EQ(count(page, "id=\"fig-map-"), 6U);
  const std::regex readings(R"re((\d+) readings \()re");
  std::size_t lines_counted = 0;
  for (const auto& [id, plot] : drawn) {
    SCOPED_TRACE(id);
    EXPECT_NE(plot.find("js-plotly-plot"), std::string::npos) << "plotly drew it";
    const bool polar = id.starts_with("fig-polar");
    // Tick labels on both axes (a polar plot: radial and angular).
    EXPECT_GE(count(plot, "class=\"xtick\""), 3U);
    EXPECT_GE(count(plot, polar ? "class=\"angularaxistick\"" : "class=\"ytick\""), polar ? 8U : 2U);
    const std::size_t marks =
        count(plot, "class=\"point\"") + count(plot, "class=\"js-line\"") + count(plot, "class=\"hm\"");
    EXPECT_GE(marks, 1U) << "its data";
    // Every reading of a line is a point on its plot.
    std::smatch m;
    if (id.starts_with("fig-line") && std::regex_search(plot, m, readings)) {
      ++lines_counted;
      EXPECT_GE(count(plot, "class=\"point\""), std::stoul(m[1]));
    }
    if (id.starts_with("fig-map")) {
      EXPECT_NE(plot.find("colorbar"), std::string::npos) << "a colour bar";
    }
  }
  EXPECT_EQ(lines_counted, count(page, "id=\"fig-line-"));
  EXPECT_FALSE(std::regex_search(without_scripts(dom), std::regex(R"re((src|href)="https?:)re")));

  const std::string png = data.dir + "/report.png";
  r = run_command("timeout 120 " + chromium + chromium_flags(temp_dir("html_report_profile_png")) +
                  "--window-size=1200,2400 --screenshot=" + shell_quote(png) + " " + shell_quote("file://" + html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // A PNG of the window's size (IHDR: width, height big-endian at bytes 16..23), and not
  // blank: a white page of this size compresses to about 10 kB, drawn plots to hundreds.
  const std::string image = read_file(png);
  ASSERT_GT(image.size(), 24U);
  const auto be32 = [&](std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(image[at])) << 24 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(image[at + 1])) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(image[at + 2])) << 8 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(image[at + 3]));
  };
  EXPECT_EQ(image.substr(1, 3), "PNG");
  EXPECT_EQ(be32(16), 1200U);
  EXPECT_EQ(be32(20), 2400U);
  EXPECT_GT(image.size(), 150000U);
}

/// The findings tests/report/look_check.js wrote into the rendered page, one a line.
std::vector<std::string> look_findings(const std::string& dom) {
  std::vector<std::string> out;
  const std::size_t open = dom.rfind("<pre id=\"ccomp-look\">");
  if (open == std::string::npos) return out;
  const std::size_t start = dom.find('>', open) + 1, end = dom.find("</pre>", start);
  std::istringstream lines(dom.substr(start, end - start));
  for (std::string line; std::getline(lines, line);) out.push_back(line);
  return out;
}

TEST(HtmlReport, LegendsMatchTheirCurvesAndMapPairsShareOneColourScale) {
  // What a reader sees, read back from what Chromium drew: each legend entry's symbol in its
  // curve's colours and every drawn curve with an entry (the down run's refitted curve was
  // drawn orange under a blue "model refitted" entry); a before/after pair of error maps on
  // one colour range with the same colour-bar labels (they were 0-30 and 0-6 um); a unit on
  // every axis.
  const Simulated& data = simulated();
  const std::string html = data.dir + "/look.html";
  CommandResult r = run_command(shell_quote(ccomp_binary()) + " check " + shell_quote(data.csv) + " -m " +
                                shell_quote(source_dir() + kModel) + " --report " + shell_quote(html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = read_file(html);
  // In the figures' data: each run's curves named as that run's.
  for (const char* name : {"model refitted, up", "model refitted, down", "model as it is, up", "model as it is, down",
                           "ISO 230-2: mean ± 2s, down"})
    EXPECT_NE(page.find(std::string("\"name\":\"") + name + "\""), std::string::npos) << name;
  // Positions name their frame.
  EXPECT_NE(page.find("\"text\":\"X axis position, machine (mm)\""), std::string::npos);
  EXPECT_NE(page.find("program coordinates of G54"), std::string::npos) << "the file's frame, in the captions";

  const std::string chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium))
    GTEST_FAIL() << "Debian's chromium is not installed at " << chromium << " (tools/install-deps.sh installs it)";
  std::string checked = page;
  const std::size_t body = checked.rfind("</body>");
  ASSERT_NE(body, std::string::npos);
  checked.insert(body, "<script>" + read_file(source_dir() + "/tests/report/look_check.js") + "</script>\n");
  const std::string checked_html = data.dir + "/look-checked.html";
  write_file(checked_html, checked);
  r = run_command("timeout 120 " + chromium + chromium_flags(temp_dir("html_look_profile")) +
                  "--enable-logging=stderr --v=0 --window-size=1280,2400 --dump-dom " +
                  shell_quote("file://" + checked_html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count(r.err, "Uncaught"), 0U) << r.err;
  const std::vector<std::string> findings = look_findings(r.out);
  ASSERT_FALSE(findings.empty()) << "the check script did not run";
  std::smatch m;
  ASSERT_TRUE(std::regex_match(findings.back(), m,
                               std::regex(R"(CHECKED legends (\d+) entries (\d+) pairs (\d+) axes (\d+))")))
      << findings.back();
  EXPECT_GE(std::stoul(m[1]), count(page, "id=\"fig-line-")) << "every line plot has its legend";
  EXPECT_GE(std::stoul(m[2]), 4 * count(page, "id=\"fig-line-")) << "measured, refitted, as it is: up and down";
  EXPECT_EQ(std::stoul(m[3]), 3U) << "XY, XZ and YZ: before and after";
  EXPECT_GE(std::stoul(m[4]), 2 * count(page, "id=\"fig-line-"));
  for (std::size_t k = 0; k + 1 < findings.size(); ++k) ADD_FAILURE() << findings[k];

  // As a reader sees them: a screenshot of the laser lines (their legends) and one of the maps
  // (each pair's colour bars), each section alone on the page, not blank and not alike.
  std::vector<std::string> images;
  for (const char* section : {"lines", "maps"}) {
    std::string alone = page;
    alone.insert(alone.find("</head>"),
                 std::string("<style>section:not(#") + section + "),nav{display:none}</style>");
    const std::string file = data.dir + "/" + section + ".html", png = data.dir + "/" + section + ".png";
    write_file(file, alone);
    r = run_command("timeout 120 " + chromium + chromium_flags(temp_dir("html_look_png")) +
                    "--window-size=1200,1400 --screenshot=" + shell_quote(png) + " " + shell_quote("file://" + file));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    images.push_back(read_file(png));
    ASSERT_GT(images.back().size(), 24U);
    EXPECT_EQ(images.back().substr(1, 3), "PNG");
    EXPECT_GT(images.back().size(), 100000U) << section << ": drawn plots, not a blank page";
  }
  EXPECT_NE(images[0], images[1]);
}

TEST(HtmlReport, FitWritesTheCheckOfTheFittedModel) {
  const Simulated& data = simulated();
  const std::string fitted = data.dir + "/fitted.yaml", html = data.dir + "/fit.html";
  const CommandResult r =
      run_command(shell_quote(ccomp_binary()) + " fit " + shell_quote(data.csv) + " -m " +
                  shell_quote(source_dir() + kModel) + " -o " + shell_quote(fitted) + " --report " + shell_quote(html));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = read_file(html);
  EXPECT_NE(page.find("<title>ccomp fit: "), std::string::npos);
  // The model checked is the one fit wrote: its SHA-256, and what fit printed as the rms
  // after is the page's rms as it is.
  EXPECT_NE(page.find(util::sha256_hex(read_file(fitted))), std::string::npos);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"re(-> (\d+\.\d+) um, max left)re"))) << r.out;
  EXPECT_NE(page.find("<b>" + m[1].str() + " &micro;m</b><span>rms residual, model as it is"), std::string::npos);
  EXPECT_GE(count(page, "class=\"plot\""), 40U);
}

}  // namespace
}  // namespace ccomp::test
