// The loop on data ccomp did not make: a reference machine written apart from ccomp's model
// code (tests/support/reference_hmc) with one hidden effect, two at once, or none, measured
// as a metrology engineer would, and the loop followed from the geometric sample model as a
// script follows `ccomp check --json`. It must name the hidden effects, end at the noise,
// never write a value beyond its scale, and on data with nothing hidden add nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "ccomp/model/model_file.hpp"
#include "metrology_loop.hpp"
#include "reference_hmc.hpp"
#include "reference_measurements.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

constexpr double kNoise = 0.0002;  // mm

struct Hidden {
  const char* name;
  std::function<void(ReferenceHmc&)> hide;
  bool thermal = false;                     ///< the plans include a warm-up run
  std::vector<std::string> named{};         ///< what the added specs must say, one each ("name: EXX, form: periodic")
  std::vector<std::string> alternatives{};  ///< a spec the data cannot tell from the named one may stand instead
  /// A number the first added spec must carry near its value: {"at: ", 130, 3} for a bump.
  struct Near {
    const char* key = nullptr;
    double value = 0, within = 0;
  } near{};
  bool spikes = false;      ///< a reading 50 um off now and then (a laser beam cut)
  double sphere_step = 15;  ///< deg: a worm wheel's teeth need finer probing of the table
  bool sphere_both_ways = false;  ///< the spheres probed turning B up, then down
};

void PrintTo(const Hidden& h, std::ostream* os) {
  *os << h.name;
}

/// The polynomial of an axis with `more` added.
std::function<double(double)> plus(std::function<double(double)> base, std::function<double(double)> more) {
  return [base, more](double v) { return base(v) + more(v); };
}

void lead_screw(ReferenceHmc& m) {
  m.EXX = plus(m.EXX, [](double x) { return 0.0015 * std::sin(2 * std::numbers::pi * x / 10.0 + 0.4); });
}

const Hidden kCases[] = {
    {.name = "nothing_hidden", .hide = [](ReferenceHmc&) {}},
    {.name = "lead_screw", .hide = lead_screw, .named = {"name: EXX, form: periodic"}},
    {.name = "backlash",
     .hide = [](ReferenceHmc& m) { m.reversal[1] = -0.0035; },
     .named = {"name: EYY, variable: vy, form: reversal"}},
    {.name = "higher_order",
     .hide = [](ReferenceHmc& m) { m.EYX = plus(m.EYX, [](double x) { return 3e-11 * x * x * x; }); },
     .named = {"name: EYX, form: polynomial"}},
    {.name = "guideway_bump",  // 6 um over some 50 mm of X's guideway, at x = 130
     .hide =
         [](ReferenceHmc& m) {
           m.EYX = plus(m.EYX, [](double x) { return 0.006 * std::exp(-0.5 * std::pow((x - 130.0) / 12.5, 2)); });
         },
     .named = {"name: EYX, form: bump"},
     .near = {"at: ", 130.0, 3.0}},
    {.name = "screw_with_spikes", .hide = lead_screw, .named = {"name: EXX, form: periodic"}, .spikes = true},
    {.name = "spindle_growth",
     .hide = [](ReferenceHmc& m) { m.spindle_growth = 0.0025; },
     .thermal = true,
     .named = {"variable: T_spindle, form: thermal"},
     .alternatives = {"variable: t, form: warmup"}},
    {.name = "screw_and_backlash",
     .hide =
         [](ReferenceHmc& m) {
           lead_screw(m);
           m.reversal[1] = -0.0035;
         },
     .named = {"name: EYY, variable: vy, form: reversal", "name: EXX, form: periodic"}},
    // The table indexes off three times a turn, 14 urad (3 um at the spheres' radius).
    {.name = "table_harmonic",
     .hide =
         [](ReferenceHmc& m) {
           m.EBB = [](double b) { return 1.2e-5 * std::cos(3 * b * std::numbers::pi / 180 + 0.6); };
         },
     .named = {"name: EBB, form: periodic, period: 120 deg"}},
    // A worm wheel of 36 teeth: a 10 deg period in the table's indexing, probed every 2.5 deg.
    {.name = "worm_wheel",
     .hide =
         [](ReferenceHmc& m) { m.EBB = [](double b) { return 1.0e-5 * std::sin(2 * std::numbers::pi * b / 10.0); }; },
     .named = {"name: EBB, form: periodic"},
     .near = {"period: ", 10.0, 0.2},
     .sphere_step = 2.5},
    // The X table's vertical straightness changes with where Z is (the table overhangs).
    {.name = "cross_axis",
     .hide =
         [](ReferenceHmc& m) {
           m.table_load = [](double x, double, double z) { return Eigen::Vector3d(0, 2e-8 * x * z, 0); };
         },
     // (A pitch of Z growing with x, less X's own, is the same on these data; so is X's
     // straightness along y growing with y z, less Z's yaw: rigid-body equivalents.)
     .named = {"name: EYX, form: cross_axis, other: z"},
     .alternatives = {"form: cross_axis"}},
    // The table's worm plays 12 urad against its wheel (2.3 um at the spheres' 190 mm),
    // seen on spheres probed turning B up, then down.
    {.name = "table_backlash",
     .hide = [](ReferenceHmc& m) { m.b_reversal = 1.2e-5; },
     .named = {"name: EBB, variable: vb, form: reversal"},
     .sphere_both_ways = true},
    // Y's screw is worn at its top: its reversal is 1 um at y = -300 and 6 um at y = +300.
    {.name = "worn_screw",
     .hide = [](ReferenceHmc& m) { m.reversal_along[1] = [](double y) { return 0.0035 + 0.0025 * y / 300.0; }; },
     .named = {"name: EYY, variable: vy, form: reversal, along: y"}},
    // The table overhangs its saddle: it sags along Y with the square of X, the more the
    // further Z has it out (2 um at the workspace's corner).
    {.name = "table_sag",
     .hide =
         [](ReferenceHmc& m) {
           m.table_load = [](double x, double, double z) { return Eigen::Vector3d(0, 4e-11 * x * x * z, 0); };
         },
     .named = {"form: cross_axis, other: z"},
     .alternatives = {"form: cross_axis"}},
    // X's glass scale grows 2 um/m per degC more than the bed it measures.
    {.name = "scale_expansion",
     .hide = [](ReferenceHmc& m) { m.x_scale_expansion = 2e-6; },
     .thermal = true,
     .named = {"name: EXX, form: scale_expansion, temperature: T_bed"}},
};

class ReferenceEffects : public ::testing::TestWithParam<Hidden> {};

TEST_P(ReferenceEffects, TheLoopNamesWhatIsHiddenEndsAtTheNoiseAndWritesNothingAbsurd) {
  const Hidden& h = GetParam();
  ReferenceHmc machine = geometric_reference();
  h.hide(machine);
  ReferencePlans plans;
  plans.noise = kNoise, plans.seed = 21, plans.line_step = 2.5, plans.thermal = h.thermal;
  plans.sphere_step = h.sphere_step, plans.sphere_both_ways = h.sphere_both_ways;
  identify::MeasurementSet data = reference_measurements(machine, measure_reference(machine, plans));
  std::vector<std::uint32_t> spiked;  // rows
  if (h.spikes) {
    for (std::size_t i = 500; i < data.observations.size(); i += 2001) {
      data.observations[i].value += 0.05;
      spiked.push_back(data.observations[i].row);
    }
  }
  // With spikes a script reruns check and fit with --robust, as fit's outliers line says.
  identify::FitOptions options;
  if (h.spikes) options.loss = identify::Loss::huber;
  const LoopResult loop =
      follow_the_loop(read_file(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml"), data, 4, options);
  EXPECT_TRUE(loop.refusals.empty()) << h.name << ": " << (loop.refusals.empty() ? "" : loop.refusals.front());
  EXPECT_TRUE(loop.ended) << h.name << ": still suggesting after " << loop.added.size() << " additions";
  if (h.spikes) {
    // The spikes are named by their rows, and what is left elsewhere is the noise.
    std::vector<std::uint32_t> named;
    for (const identify::FitReport::Outlier& o : loop.last.outliers) named.push_back(o.row);
    std::sort(named.begin(), named.end());
    EXPECT_EQ(named, spiked) << h.name;
    const model::ForwardModel fitted(model::parse_machine_model(loop.text, "fitted.yaml"));
    const Eigen::VectorXd r = identify::residuals(fitted, identify::model_parameters(fitted), data);
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < data.observations.size(); ++i)
      if (!std::binary_search(spiked.begin(), spiked.end(), data.observations[i].row))
        sum += r[static_cast<Eigen::Index>(i)] * r[static_cast<Eigen::Index>(i)], ++count;
    EXPECT_LE(std::sqrt(sum / static_cast<double>(count)), 1.3 * kNoise) << h.name;
  } else {
    EXPECT_LE(loop.last.rms_after, 1.3 * kNoise) << h.name;
  }
  ASSERT_EQ(loop.added.size(), h.named.size()) << h.name << ": added " << ::testing::PrintToString(loop.added);
  for (std::size_t i = 0; i < h.named.size(); ++i) {
    const bool named = loop.added[i].find(h.named[i]) != std::string::npos;
    const bool alternative = i < h.alternatives.size() && loop.added[i].find(h.alternatives[i]) != std::string::npos;
    EXPECT_TRUE(named || alternative) << h.name << ": added " << loop.added[i] << ", expected " << h.named[i];
    if (alternative && !named) {
      EXPECT_FALSE(loop.ties.empty()) << "a tie is said, with the measurement that would decide it";
    }
  }
  if (h.near.key && !loop.added.empty()) {
    const std::string& spec = loop.added.front();
    const auto at = spec.find(h.near.key);
    ASSERT_NE(at, std::string::npos) << spec;
    EXPECT_NEAR(std::stod(spec.substr(at + std::string(h.near.key).size())), h.near.value, h.near.within) << spec;
  }
}

// Null sets: the reference with nothing beyond the sample model's terms, measured with
// other noise draws and a warm-up run (two sensors, time): the loop adds nothing, and says
// nothing is missing.
TEST(ReferenceNull, NothingHiddenNothingSuggestedWhateverTheNoiseDraw) {
  for (const unsigned seed : {31U, 32U, 33U}) {
    ReferencePlans plans;
    plans.noise = kNoise, plans.seed = seed, plans.line_step = 2.5, plans.thermal = true;
    const LoopResult loop = follow_the_loop(read_file(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml"),
                                            reference_measurements(geometric_reference(), measure_reference(geometric_reference(), plans)), 2);
    EXPECT_TRUE(loop.ended && loop.added.empty())
        << "seed " << seed << ": added " << ::testing::PrintToString(loop.added);
    EXPECT_TRUE(loop.unexplained.empty()) << "seed " << seed << ": " << loop.unexplained;
    EXPECT_LE(loop.last.rms_after, 1.3 * kNoise) << "seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Reference, ReferenceEffects, ::testing::ValuesIn(kCases),
                         [](const auto& test) { return std::string(test.param.name); });

}  // namespace
}  // namespace ccomp::test
