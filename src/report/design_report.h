// What `gyrosid design` writes beside the trajectory: coverage.png (the trajectory's samples over (T, w)
// with the application envelope shaded) and report.md (the programme, the predicted accuracy per flight
// against the starting programme and any reference trajectories, the solver's summary).
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "design/design.h"

namespace gyrosid {

// design.json's and evaluation.json's parts: a prediction; a design with its solver's summary and the
// starting programme's prediction; `provenance` is stored as it is.
nlohmann::json prediction_json(const design::Prediction& prediction);
nlohmann::json design_json(const design::DesignResult& result, const nlohmann::json& provenance);

// Samples (probe temperature, measured rate) of `observations` over the envelope's samples (grey) and its
// domain (dashed box).
void plot_design_coverage(const std::filesystem::path& png, const design::Observations& observations,
                          const design::Envelope& envelope, const std::string& title);

// A design for a prior over sensors (sensor/sensor_prior.h): the design's and the compared trajectories'
// predictions on one member.
struct PriorMemberPredictions {
  std::string name, origin;
  double weight = 1.0;
  design::Prediction design;
  std::vector<std::pair<std::string, design::Prediction>> compared;  // by trajectory name
};
// design.json's "prior": every member's predictions, and per flight the spread over the members - the weighted
// mean, least and largest of the design's cof_m and of its gain cof_m(compared) / cof_m(design) on each compared
// trajectory.
nlohmann::json prior_json(const std::string& name, const std::string& source, const std::vector<PriorMemberPredictions>& members);

struct DesignReportInput {
  const design::DesignResult* result = nullptr;  // null for an evaluation only
  std::vector<std::pair<std::string, design::Prediction>> compared;  // reference trajectories by name
  std::vector<PriorMemberPredictions> prior;      // a design for a prior of more than one sensor
  std::string command;                                            // how it was made
  std::string model, sensor, solver;
};
std::string design_report_markdown(const DesignReportInput& input);

// A designed programme's files in `dir`: trajectory.yaml (what `gyrosid simulate --trajectory` takes),
// setpoints.csv (the chamber's and table's set points) and design.json (`design_file`), each atomically.
void write_designed_programme(const std::filesystem::path& dir, const TrajectorySpec& trajectory, const nlohmann::json& design_file);

// --evaluate's evaluation.json: every evaluated trajectory's prediction, by the name it was given (`evaluated`:
// the last entries of report.compared, after a cof_minimax reference).
nlohmann::json evaluation_json(const DesignReportInput& report, const std::vector<std::string>& evaluated, const nlohmann::json& provenance);

}  // namespace gyrosid
