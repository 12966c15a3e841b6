#include "ccomp/model/term_forms.hpp"

#include <algorithm>

namespace ccomp::model {

const std::vector<TermFormInfo>& term_forms() {
  // In TermForm's order (term_form(TermForm) indexes it; the Jacobian suite checks the order).
  static const std::vector<TermFormInfo> kForms{
      forms::constant(),       forms::polynomial(),     forms::table(),           forms::periodic(),
      forms::reversal(),       forms::thermal_linear(), forms::thermal_warmup(),  forms::scale_expansion(),
      forms::cross_axis(),     forms::bump(),
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
