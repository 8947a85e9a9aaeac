// The grey-box model's named views (core/packed_layout.h): the coefficient spans cover exactly the columns
// of the terms they name, in greybox_terms' order, and theta's spans cover exactly the coordinates of their
// group, for every structure the options can make.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "model/greybox_fit.h"
#include "model/greybox_prior.h"

namespace gyrosid {
namespace {

std::vector<GreyboxOptions> structures() {
  std::vector<GreyboxOptions> all;
  for (int bias_order : {0, 2, 3}) {
    for (bool surface : {true, false}) {
      for (int flags = 0; flags < 16; ++flags) {
        GreyboxOptions o;
        o.bias_order = bias_order;
        o.scale_factor = surface ? ScaleFactorForm::surface : ScaleFactorForm::polynomial;
        o.sf_temperature_order = flags % 3;
        o.sf_rate_order = 1 + flags % 4;
        o.shupe = flags & 1, o.asymmetry = flags & 2, o.g_sensitivity = flags & 4, o.thermal_lag = flags & 8;
        all.push_back(o);
      }
    }
  }
  return all;
}

// The span each term kind's columns belong to; the separable scale factor's columns split at eps_T's order.
Span expected_span(const GreyboxCoefficients& at, std::string_view kind, int column, const GreyboxOptions& o) {
  if (kind == "bias" || kind == "bias_temperature") return at.bias;
  if (kind == "scale_factor") return column < o.sf_temperature_order ? at.sf_temperature : at.sf_rate;
  if (kind == "scale_factor_surface") return at.surface;
  if (kind == "shupe") return at.shupe;
  if (kind == "asymmetry") return at.asymmetry;
  if (kind == "channel") return at.g_sensitivity;
  ADD_FAILURE() << "a grey-box term of kind " << kind << " has no span";
  return {};
}

TEST(GreyboxLayouts, CoefficientSpansAreTheTermsColumnsInOrder) {
  for (const GreyboxOptions& o : structures()) {
    const GreyboxCoefficients at(o);
    const std::vector<Term> terms = greybox_terms(o);
    ASSERT_EQ(at.size, total_columns(terms));
    std::map<Eigen::Index, int> seen;  // span offset -> columns found in it
    Eigen::Index column = 0;
    for (const Term& t : terms) {
      for (int j = 0; j < t.size(); ++j, ++column) {
        const Span s = expected_span(at, t.kind(), j, o);
        ASSERT_TRUE(s.present()) << t.kind();
        EXPECT_EQ(s.at(seen[s.offset]++), column) << t.kind() << " column " << j;
      }
    }
    for (const Span& s : {at.bias, at.sf_temperature, at.sf_rate, at.surface, at.shupe, at.asymmetry, at.g_sensitivity}) {
      EXPECT_EQ(s.present() ? seen[s.offset] : 0, s.size);
    }
  }
}

TEST(GreyboxLayouts, ThetaSpansAreTheCoordinatesOfTheirGroup) {
  for (const GreyboxOptions& o : structures()) {
    if (o.scale_factor != ScaleFactorForm::surface) continue;  // theta is defined on the surface form only
    const GreyboxThetaLayout at(o);
    const std::vector<GreyboxCoordinate> coordinates = greybox_coordinates(o);
    ASSERT_EQ(at.size, static_cast<Eigen::Index>(coordinates.size()));
    const std::map<std::string, Span> groups{{"bias", at.bias},       {"surface", at.surface},
                                             {"shupe", at.shupe},     {"asymmetry", at.asymmetry},
                                             {"g_sensitivity", at.g_sensitivity}, {"lag", at.lag}};
    std::map<std::string, Eigen::Index> counted;
    for (std::size_t i = 0; i < coordinates.size(); ++i) {
      const Span s = groups.at(coordinates[i].group);
      EXPECT_EQ(s.at(counted[coordinates[i].group]++), static_cast<Eigen::Index>(i)) << coordinates[i].name;
    }
    for (const auto& [group, span] : groups) EXPECT_EQ(counted[group], span.size) << group;
  }
}

}  // namespace
}  // namespace gyrosid
