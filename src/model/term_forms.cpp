#include "ccomp/model/term_forms.hpp"

#include <algorithm>

namespace ccomp::model {

const std::vector<TermFormInfo>& term_forms() {
  static const std::vector<TermFormInfo> kForms{
      {TermForm::constant, {"constant"}, {"value"}, "a constant offset or angle: a location error, a squareness"},
      {TermForm::polynomial,
       {"polynomial"},
       {"coefficients"},
       "a smooth error along an axis: positioning, straightness, an angular error motion"},
      {TermForm::table,
       {"table"},
       {"at", "values", "interpolation"},
       "an error read at targets (a laser run), through its values"},
      {TermForm::periodic,
       {"periodic"},
       {"period", "harmonics"},
       "a lead screw's or a scale's pitch, a worm wheel's teeth, a table's once-per-turn errors"},
      {TermForm::reversal,
       {"reversal"},
       {"reversal", "along"},
       "backlash, lost motion: an error switched by the approach, of a linear or a rotary axis, constant or "
       "varying along an axis (a screw worn more where it works most)"},
      {TermForm::thermal_linear,
       {"thermal", "thermal_linear"},
       {"coefficient", "reference"},
       "a drift with a sensor's temperature"},
      {TermForm::thermal_warmup, {"warmup"}, {"amplitude", "time_constant"}, "a warm-up drift, first order in time"},
      {TermForm::scale_expansion,
       {"scale_expansion"},
       {"temperature", "coefficient", "reference"},
       "a scale growing with its temperature"},
      {TermForm::cross_axis,
       {"cross_axis"},
       {"other", "coefficients"},
       "an error of one axis varying smoothly with another's position: a load, an overhang sagging, 2-D Abbe errors"},
      {TermForm::bump, {"bump"}, {"at", "width", "amplitude"}, "a local defect: a guideway's bump, a scale joint"},
  };
  return kForms;
}

const TermFormInfo* term_form(std::string_view name) {
  const auto& forms = term_forms();
  const auto it = std::find_if(forms.begin(), forms.end(), [name](const TermFormInfo& f) {
    return std::find(f.names.begin(), f.names.end(), name) != f.names.end();
  });
  return it == forms.end() ? nullptr : &*it;
}

}  // namespace ccomp::model
