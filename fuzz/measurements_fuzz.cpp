// libFuzzer target: measurement CSV files (identify::parse_measurements, what
// read_measurements does with a file's text), read against the sample HMC model (sensors,
// a rotary axis) and summarised as fit and check do next. A small file (up to 200 rows) is
// then read against a one-axis model with one free cubic, fitted, and its noise floor and
// residuals taken, as `fit` and `check` do: the short strokes, single runs, few targets and
// one-direction runs of fuzz/seeds/measurements reach the fit's "nothing identifiable"
// path there. A non-finite fitted value or residual is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ccomp/identify/check.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "fuzz_outcome.hpp"

namespace {

const ccomp::model::MachineModel& hmc() {
  static const ccomp::model::MachineModel model =
      ccomp::model::load_machine_model(CCOMP_SOURCE_DIR "/samples/machines/hmc-xyzb.yaml");
  return model;
}

const ccomp::model::ForwardModel& one_axis() {
  static const ccomp::model::MachineModel machine = ccomp::model::parse_machine_model(
      "name: one-axis\nmax_correction: 1 mm\naxes:\n  X: {type: linear, min: -1000, max: 1000}\n"
      "  Y: {type: linear, min: -250, max: 250}\n  Z: {type: linear, min: -400, max: 400}\n"
      "chain:\n  workpiece:\n    - {link: Y, axis: Y, direction: [0, -1, 0]}\n"
      "    - {link: X, axis: X, direction: [-1, 0, 0]}\n  tool:\n    - {link: Z, axis: Z, direction: [0, 0, 1]}\n"
      "    - {link: tool, tool_length: [0, 0, -1]}\n"
      "terms:\n  - {name: EXX, form: polynomial, unit: um, coefficients: [0, 0, 0, 0], fit: true}\n",
      "one-axis.yaml");
  static const ccomp::model::ForwardModel model(machine);
  return model;
}

constexpr std::size_t kFittedRows = 200;

void fit_small(const std::string& text) {
  const ccomp::model::ForwardModel& model = one_axis();
  ccomp::identify::MeasurementSet set;
  ccomp::identify::parse_measurements(text, "fuzz.csv", model.machine(), {}, set);
  ccomp::identify::summarize(set, model.machine());
  const ccomp::identify::CheckReport check = ccomp::identify::check(model, set);
  const ccomp::identify::FitReport fit = ccomp::identify::fit(model, set);
  if (!fit.all_parameters.allFinite() || !std::isfinite(fit.rms_after) || !std::isfinite(check.rms) ||
      !std::isfinite(check.noise_floor)) {
    std::fprintf(stderr, "finding: a non-finite fit or check of a small measurement file\n");
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ccomp::model::MachineModel& model = hmc();
  const std::string text(reinterpret_cast<const char*>(data), size);
  ccomp::fuzz::read_or_refuse([&] {
    ccomp::identify::MeasurementSet set;
    ccomp::identify::parse_measurements(text, "fuzz.csv", model, {}, set);
    ccomp::identify::summarize(set, model);
  });
  std::size_t rows = 0;
  for (const char c : text) rows += c == '\n' ? 1 : 0;
  if (rows <= kFittedRows) ccomp::fuzz::read_or_refuse([&] { fit_small(text); });
  return 0;
}
