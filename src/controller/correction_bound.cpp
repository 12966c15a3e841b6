#include "correction_bound.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "ccomp/error.hpp"

namespace ccomp::controller {

void check_correction(const model::MachineModel& machine, double correction, bool rotary, std::string_view what,
                      std::string_view where) {
  const double bound = rotary ? machine.max_correction * model::kRotaryBoundPerMm : machine.max_correction;
  if (std::abs(correction) <= bound) return;
  if (!std::isfinite(correction))
    throw Error(ErrorKind::safety, fmt::format("{} at {} is not a number ({}): the model's error there is not finite; "
                                               "is the model right for this machine?",
                                               what, where, correction));
  if (rotary)
    throw Error(ErrorKind::safety,
                fmt::format("{} at {} is {:.4g} deg, beyond the model's bound of {:.4g} deg (max_correction, {:g} mrad "
                            "per mm): is the model right for this machine?",
                            what, where, correction * 180.0 / std::numbers::pi, bound * 180.0 / std::numbers::pi,
                            model::kRotaryBoundPerMm * 1e3));
  // The main job's 4 decimals, or 6 digits of one beyond any machine (a coefficient of 1e308).
  const std::string size =
      std::abs(correction) < 1e6 ? fmt::format("{:.4f}", correction) : fmt::format("{:.6g}", correction);
  throw Error(ErrorKind::safety, fmt::format("{} at {} is {} mm, beyond the model's bound of {} mm "
                                             "(max_correction): is the model right for this machine?",
                                             what, where, size, machine.max_correction));
}

void check_written(double value, std::string_view file_kind, std::string_view where) {
  if (std::isfinite(value)) return;
  throw Error(ErrorKind::safety,
              fmt::format("the {} table would hold {} at {}: nothing is written", file_kind, value, where));
}

}  // namespace ccomp::controller
