#include "contact/force_law.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tolerance.h"

namespace camdyn {
namespace {

ForceLaw law_of(ContactModel model, double e = 0.5) {
  ForceLaw law;
  law.model = model;
  law.stiffness = 1e9;
  law.exponent = 1.5;
  law.restitution = e;
  law.damping = 100.0;
  return law;
}

TEST(ForceLaw, ChiFactorsFollowThePapers) {
  EXPECT_DOUBLE_EQ(law_of(ContactModel::hunt_crossley, 0.5).chi(), 3.0 * 0.5 / 2.0);
  EXPECT_DOUBLE_EQ(law_of(ContactModel::lankarani_nikravesh, 0.5).chi(), 3.0 * (1 - 0.25) / 4.0);
  EXPECT_DOUBLE_EQ(law_of(ContactModel::flores, 0.5).chi(), 8.0 * 0.5 / (5.0 * 0.5));
  EXPECT_EQ(law_of(ContactModel::hertz).chi(), 0.0);
  EXPECT_EQ(law_of(ContactModel::hunt_crossley, 1.0).chi(), 0.0);
}

TEST(ForceLaw, NeverAdhesiveAndZeroWhenApart) {
  for (ContactModel m : {ContactModel::hertz, ContactModel::kelvin_voigt, ContactModel::hunt_crossley,
                         ContactModel::lankarani_nikravesh, ContactModel::flores}) {
    const ForceLaw law = law_of(m);
    EXPECT_EQ(law.force(-1e-6, -10.0, 1.0), 0.0);
    EXPECT_EQ(law.force(0.0, 10.0, 1.0), 0.0);
    EXPECT_GE(law.force(1e-6, -100.0, 1.0), 0.0);  // fast withdrawal: clamped, not pulling
  }
}

TEST(ForceLaw, ElasticEnergyDerivativeIsElasticForce) {
  const ForceLaw law = law_of(ContactModel::hertz);
  for (double delta : {1e-7, 1e-6, 1e-5, 1e-4}) {
    const double h = delta * 1e-5;
    const double fd = (law.elastic_energy(delta + h) - law.elastic_energy(delta - h)) / (2 * h);
    EXPECT_NEAR(fd / law.elastic_force(delta), 1.0, test::kFiniteDifference);
  }
}

TEST(ForceLaw, ClampSwitchHasTheSignOfTheUnclampedForce) {
  for (ContactModel m : {ContactModel::kelvin_voigt, ContactModel::hunt_crossley, ContactModel::lankarani_nikravesh,
                         ContactModel::flores}) {
    const ForceLaw law = law_of(m, 0.3);
    for (double rate : {-50.0, -5.0, -0.5, 0.0, 0.5, 5.0}) {
      const double delta = 1e-6;
      const double unclamped = law.force(delta, rate, 1.0);
      const double sw = law.clamp_switch(delta, rate, 1.0);
      if (unclamped > 0.0)
        EXPECT_GT(sw, 0.0) << to_string(m) << " rate " << rate;
      else
        EXPECT_LE(sw, 0.0) << to_string(m) << " rate " << rate;
    }
  }
}

TEST(ForceLaw, EveryLawHasAFormAndItsDampingFollowsIt) {
  for (const EnumName<ContactModel>& entry : enum_names(ContactModel{})) {
    const ForceLaw law = law_of(entry.value, 0.5);
    const double delta = 1e-6, elastic = law.elastic_force(delta);
    switch (force_form(entry.value)) {
      case ForceForm::elastic:  // no damping, nothing to switch on
        EXPECT_EQ(law.chi(), 0.0) << entry.name;
        EXPECT_EQ(law.force(delta, 1.0, 1.0), elastic) << entry.name;
        EXPECT_FALSE(law.has_clamp_switch()) << entry.name;
        break;
      case ForceForm::viscous:  // the config's c
        EXPECT_EQ(law.chi(), 0.0) << entry.name;
        EXPECT_EQ(law.force(delta, 1.0, 1.0), elastic + law.damping * 1.0) << entry.name;
        EXPECT_TRUE(law.has_clamp_switch()) << entry.name;
        break;
      case ForceForm::hysteresis:  // χ(e) > 0 for e < 1
        EXPECT_GT(law.chi(), 0.0) << entry.name;
        EXPECT_EQ(law.force(delta, 1.0, 1.0), elastic * (1.0 + law.chi())) << entry.name;
        EXPECT_TRUE(law.has_clamp_switch()) << entry.name;
        break;
    }
  }
  EXPECT_EQ(force_form(ContactModel::hertz), ForceForm::elastic);
  EXPECT_EQ(force_form(ContactModel::kelvin_voigt), ForceForm::viscous);
  EXPECT_EQ(law_words(ForceForm::viscous), "'kelvin_voigt'");
  EXPECT_EQ(law_words(ForceForm::hysteresis), "'hunt_crossley' or 'lankarani_nikravesh' or 'flores'");
}

TEST(ForceLaw, StiffnessFromMaterialsMatchesHertz) {
  // Steel on steel, R* = 8 mm: K = 4/3 E* sqrt(R*).
  const double E = 210e9, nu = 0.3;
  const double e_star = E / (2 * (1 - nu * nu));
  const double k = stiffness_from_materials(E, nu, E, nu, 0.04, 0.01, false, 0.0);
  EXPECT_NEAR(k, 4.0 / 3.0 * e_star * std::sqrt(0.008), 1e-6 * k);
}

}  // namespace
}  // namespace camdyn
