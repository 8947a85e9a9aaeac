// The typed notes a fit writes into its summary's details (model/fit_notes.h): what is written is read back
// field for field, through a model file's summary too, and nothing unset is written.
#include <gtest/gtest.h>

#include "core/solve_summary.h"
#include "model/fit_notes.h"

namespace gyrosid {
namespace {

FitNotes every_note() {
  FitNotes n;
  n.nodes = 17;
  n.parameters = 9;
  n.physics_left_out = PhysicsLeftOut{{"bias v^1", "sf_temperature v^2"}, "the temperature stays within 0.2 C of 25 C"};
  n.data_share = {{"bias", 0.25}, {"surface", 0.875}};  // in the details' (alphabetical) order
  n.predictive_sigma = PredictiveSigma{1.5, 4.25, -40.0, 300.0};
  n.physics_note = "the ridge, not the recording, sets the terms in it";
  n.noise_choice = "white (option noise=white)";
  n.noise_identification = "white + random walk: ...";
  n.ridge_lambda = 0.03125;
  return n;
}

void expect_same(const FitNotes& a, const FitNotes& b) {
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.parameters, b.parameters);
  ASSERT_EQ(a.physics_left_out.has_value(), b.physics_left_out.has_value());
  if (a.physics_left_out) {
    EXPECT_EQ(a.physics_left_out->columns, b.physics_left_out->columns);
    EXPECT_EQ(a.physics_left_out->note, b.physics_left_out->note);
  }
  EXPECT_EQ(a.data_share, b.data_share);
  ASSERT_EQ(a.predictive_sigma.has_value(), b.predictive_sigma.has_value());
  if (a.predictive_sigma) {
    EXPECT_EQ(a.predictive_sigma->rms_dph, b.predictive_sigma->rms_dph);
    EXPECT_EQ(a.predictive_sigma->max_dph, b.predictive_sigma->max_dph);
    EXPECT_EQ(a.predictive_sigma->max_at_temp_c, b.predictive_sigma->max_at_temp_c);
    EXPECT_EQ(a.predictive_sigma->max_at_rate_dps, b.predictive_sigma->max_at_rate_dps);
  }
  EXPECT_EQ(a.physics_note, b.physics_note);
  EXPECT_EQ(a.noise_choice, b.noise_choice);
  EXPECT_EQ(a.noise_identification, b.noise_identification);
  EXPECT_EQ(a.ridge_lambda, b.ridge_lambda);
}

TEST(FitNotes, WhatIsWrittenIsReadBackBesideTheOtherDetails) {
  nlohmann::json details = {{"samples", 1200}, {"rms_residual_dph", 0.5}};
  write_fit_notes(every_note(), details);
  EXPECT_EQ(details["samples"], 1200);  // the fit's own log is kept
  EXPECT_EQ(details["rms_residual_dph"], 0.5);
  EXPECT_EQ(details["predictive_sigma"]["grid"], "surface nodes");
  expect_same(fit_notes_of(details), every_note());
}

TEST(FitNotes, SurviveAModelFilesSummary) {
  SolveSummary s;
  s.solver = "greybox";
  write_fit_notes(every_note(), s.details);
  const nlohmann::json file = s;  // as save_model writes it
  expect_same(fit_notes_of(solve_summary_from_json(nlohmann::json::parse(file.dump())).details), every_note());
}

TEST(FitNotes, NothingUnsetIsWrittenOrRead) {
  nlohmann::json details = nlohmann::json::object();
  write_fit_notes(FitNotes{}, details);
  EXPECT_TRUE(details.empty());
  expect_same(fit_notes_of(details), FitNotes{});
  expect_same(fit_notes_of(nlohmann::json()), FitNotes{});  // a summary without details
}

TEST(FitNotes, SizeNamesNodesBeforeCoefficients) {
  FitNotes n;
  EXPECT_EQ(n.size(), "");
  n.parameters = 13;
  EXPECT_EQ(n.size(), "13 coefficients");
  n.nodes = 40;
  EXPECT_EQ(n.size(), "40 nodes");
}

}  // namespace
}  // namespace gyrosid
