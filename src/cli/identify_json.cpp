#include "identify_json.hpp"

#include <cmath>

#include "ccomp/util/json.hpp"

namespace ccomp::cli {
namespace {

/// A parameter in the model file's units (um, urad, or as the term writes it).
double readable(const model::ForwardModel& forward, const identify::FittedParameter& p, double v) {
  const model::ErrorTermSpec& t = forward.machine().terms[p.term];
  return v / t.parameter_unit[p.index - forward.parameter_offset(p.term)];
}

void data_fields(util::JsonWriter& j, const identify::MeasurementSet& data) {
  j.field("observations", data.observations.size()).key("files").begin_array();
  for (const std::string& f : data.files) j.value(f);
  j.end_array().key("sources").begin_array();
  for (const std::string& s : data.sources) j.value(s);
  j.end_array();
}

void parameters(util::JsonWriter& j, const model::ForwardModel& forward, const identify::FitReport& r) {
  j.key("parameters").begin_array();
  for (const identify::FittedParameter& p : r.parameters) {
    j.begin_object().field("label", p.label).field("term", forward.machine().terms[p.term].name);
    j.field("before", readable(forward, p, p.before)).field("after", readable(forward, p, p.after));
    j.field("uncertainty", readable(forward, p, p.uncertainty)).field("identified", p.identified).end_object();
  }
  j.end_array();
}

void strings(util::JsonWriter& j, std::string_view key, const std::vector<std::string>& values) {
  j.key(key).begin_array();
  for (const std::string& v : values) j.value(v);
  j.end_array();
}

}  // namespace

std::string fit_json(const model::ForwardModel& forward, const identify::MeasurementSet& data,
                     const identify::FitReport& r, const std::string& output, bool written) {
  util::JsonWriter j;
  j.begin_object().field("command", "fit").field("model", forward.machine().name);
  data_fields(j, data);
  j.field("output", output).field("written", written);
  j.field("free_parameters", r.parameters.size()).field("identified_combinations", r.rank);
  j.field("condition_number", r.condition_number).field("significant", r.significant);
  j.field("iterations", r.iterations).field("converged", r.converged);
  j.field("rms_before_um", r.rms_before * 1e3).field("rms_after_um", r.rms_after * 1e3);
  j.field("max_after_um", r.max_after * 1e3).key("per_source").begin_array();
  for (std::size_t s = 0; s < data.sources.size() && s < r.source_rms_before.size(); ++s)
    j.begin_object()
        .field("source", data.sources[s])
        .field("rms_before_um", r.source_rms_before[s] * 1e3)
        .field("rms_after_um", r.source_rms_after[s] * 1e3)
        .end_object();
  j.end_array();
  parameters(j, forward, r);
  strings(j, "unidentifiable", r.unidentifiable);
  j.key("outliers").begin_array();
  for (const identify::FitReport::Outlier& o : r.outliers)
    j.begin_object()
        .field("file", data.files[o.file])
        .field("row", o.row)
        .field("residual_um", o.residual * 1e3)
        .end_object();
  j.end_array();
  strings(j, "refusals", r.refusals);
  return j.end_object().text();
}

std::string nine_line_json(const model::ForwardModel& forward, const identify::MeasurementSet& data,
                           const identify::NineLineReport& r, const std::string& output) {
  util::JsonWriter j;
  j.begin_object().field("command", "nine-line").field("model", forward.machine().name);
  data_fields(j, data);
  if (output.empty())
    j.key("output").null();
  else
    j.field("output", output);
  j.field("free_parameters", r.fit.parameters.size()).field("identified_combinations", r.fit.rank);
  j.field("rms_before_um", r.fit.rms_before * 1e3).field("rms_after_um", r.fit.rms_after * 1e3);
  parameters(j, forward, r.fit);
  j.key("squareness").begin_array();
  for (const identify::LineSquareness& q : r.squareness) {
    j.begin_object().field("iso", q.iso).field("urad", q.value * 1e6).field("symbol", q.seed);
    j.field("symbol_urad", q.seed_sign * q.value * 1e6).end_object();
  }
  j.end_array().key("placement_sensitivity").begin_array();
  for (const identify::PlacementSensitivity& s : r.sensitivity) {
    double unit = 1.0;
    for (const identify::FittedParameter& p : r.fit.parameters)
      if (p.label == s.parameter)
        unit = forward.machine().terms[p.term].parameter_unit[p.index - forward.parameter_offset(p.term)];
    j.begin_object().field("parameter", s.parameter).field("per_mm", s.per_mm / unit).field("line", s.line);
    j.end_object();
  }
  j.end_array().key("placements").begin_array();
  for (const auto& [inset, value] : r.placements)
    j.begin_object().field("inset", inset).field("sensitivity", value).end_object();
  j.end_array().field("recommended_inset", r.recommended_inset);
  return j.end_object().text();
}

std::string simulate_json(const model::MachineModel& m, const identify::MeasurementSet& set,
                          const std::string& output) {
  util::JsonWriter j;
  j.begin_object().field("command", "simulate").field("model", m.name).field("output", output);
  j.field("observations", set.observations.size());
  strings(j, "sources", set.sources);
  return j.end_object().text();
}

std::string check_json(const model::MachineModel& m, const identify::CheckReport& r, const identify::Diagnosis& d) {
  util::JsonWriter j;
  j.begin_object().field("command", "check").field("model", m.name).field("model_sha256", m.sha256);
  j.field("observations", r.observations).field("rms_um", r.rms * 1e3).field("max_um", r.max * 1e3);
  // Nothing measured, nothing estimated: null, not 0.
  const auto measured = [&](double v) { return r.observations > 0 ? v * 1e3 : std::nan(""); };
  j.field("noise_floor_um", measured(r.noise_floor)).field("noise_method", r.noise_method);
  j.field("rms_refit_um", d.skipped.empty() ? measured(d.rms_refit) : std::nan(""));
  j.key("sources").begin_array();
  for (const identify::SourceResidual& s : r.sources) {
    j.begin_object().field("source", s.source).field("observations", s.observations).field("rms_um", s.rms * 1e3);
    j.field("max_um", s.max * 1e3).end_object();
  }
  j.end_array().key("regions").begin_array();
  for (const identify::Region& g : d.regions) {
    j.begin_object().field("variable", g.variable).field("from", g.from).field("to", g.to);
    j.field("rms_um", g.rms * 1e3).field("ratio", g.ratio).end_object();
  }
  j.end_array();
  j.field("candidates_tried", d.candidates_tried).field("unproven", d.unproven).field("implausible", d.implausible);
  if (d.origin_misfit) {
    const identify::OriginMisfit& o = *d.origin_misfit;
    j.key("origin_misfit").begin_object().key("shift_mm").begin_array();
    for (int k = 0; k < 3; ++k) j.value(o.shift[k]);
    j.end_array().field("rms_before_um", o.rms_before * 1e3).field("rms_after_um", o.rms_after * 1e3);
    j.field("bic_delta", o.bic_delta).field("significance", o.significance).end_object();
  } else {
    j.key("origin_misfit").null();
  }
  j.key("suggestions").begin_array();
  for (const identify::Suggestion& s : d.suggestions) {
    j.begin_object().field("rank", s.rank).field("effect", s.effect).field("error", s.error).field("term", s.term);
    j.field("variable", s.variable).field("form", s.form);
    j.field("period", s.period > 0 ? s.period : std::nan(""));
    j.field("period_uncertainty", s.period > 0 ? s.period_uncertainty : std::nan(""));
    j.key("aliases").begin_array();
    for (const double a : s.aliases) j.value(a);
    j.end_array().field("aliasing", s.aliasing);
    j.field("spec", s.spec).field("rms_before_um", s.rms_before * 1e3).field("rms_after_um", s.rms_after * 1e3);
    j.field("bic_delta", s.bic_delta).field("significance", s.significance).field("held_out", s.held_out);
    j.field("held_out_by", s.held_out_by).field("refitted", s.refitted).end_object();
  }
  j.end_array().key("ties").begin_array();
  for (const identify::Tie& t : d.ties) {
    j.begin_object().field("first", t.first + 1).field("second", t.second + 1).field("correlation", t.correlation);
    j.field("measurement", t.measurement).end_object();
  }
  j.end_array();
  const std::string nothing = identify::nothing_identifiable(d.refit);
  for (const auto& [key, text] : {std::pair<const char*, const std::string&>{"unexplained", d.unexplained},
                                  {"skipped", d.skipped},
                                  {"nothing_identifiable", nothing}}) {
    if (text.empty())
      j.key(key).null();
    else
      j.field(key, text);
  }
  return j.end_object().text();
}

}  // namespace ccomp::cli
