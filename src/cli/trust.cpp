#include "trust.hpp"

#include <fmt/format.h>

namespace ccomp::cli {

compensate::ProgramTrust trust_on_file(const std::string& input, const model::ForwardModel& model,
                                       const std::optional<model::FitInformation>& info,
                                       compensate::CheckOptions options) {
  if (!info) return {};
  compensate::TrustGauge gauge(model, info);
  options.pose = [&gauge](const model::ChainQ& q, const model::Conditions& c, std::uint32_t line) {
    gauge.add(q, c, line);
  };
  options.progress = nullptr;
  options.warning = nullptr;
  gcode::LineSource program = gcode::LineSource::open(input);
  (void)compensate::predict(program, model, options);
  return gauge.result();
}

void trust_fields(util::JsonWriter& j, const std::optional<compensate::ProgramTrust>& trust, double added,
                  const std::string& why_none) {
  if (trust && trust->known) {
    j.field("expected_after_um", (trust->expected_after + added) * 1e3);
    j.field("after_bound_um", (trust->after_bound + added) * 1e3);
  } else {
    j.key("expected_after_um").null();
    j.key("after_bound_um").null();
  }
  j.key("extrapolation").begin_array();
  if (trust)
    for (const std::string& e : trust->extrapolation) j.value(e);
  j.end_array();
  j.field("trust", trust ? compensate::trust_text(*trust) : why_none);
}

}  // namespace ccomp::cli
