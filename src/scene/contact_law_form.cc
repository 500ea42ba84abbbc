#include "scene/contact_law_form.h"

#include <stdexcept>
#include <string>

#include "scene/enum_names.h"

namespace camdyn {

// A new law: its word in scene/scene.h, a case here and in ForceLaw::chi()
// (contact/force_law.cc).
ForceForm force_form(ContactModel model) {
  switch (model) {
    case ContactModel::hertz:
      return ForceForm::elastic;
    case ContactModel::kelvin_voigt:
      return ForceForm::viscous;
    case ContactModel::hunt_crossley:
    case ContactModel::lankarani_nikravesh:
    case ContactModel::flores:
      return ForceForm::hysteresis;
  }
  throw std::invalid_argument("not a ContactModel value");
}

std::string law_words(ForceForm form) {
  std::string words;
  for (const EnumName<ContactModel>& law : enum_names(ContactModel{})) {
    if (force_form(law.value) != form) continue;
    words += (words.empty() ? "'" : " or '") + std::string(law.name) + "'";
  }
  return words;
}

}  // namespace camdyn
