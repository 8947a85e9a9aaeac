#include "model/fit_notes.h"

namespace gyrosid {

std::string FitNotes::size() const {
  if (nodes) return std::to_string(*nodes) + " nodes";
  if (parameters) return std::to_string(*parameters) + " coefficients";
  return "";
}

void write_fit_notes(const FitNotes& n, nlohmann::json& details) {
  if (n.nodes) details["nodes"] = *n.nodes;
  if (n.parameters) details["parameters"] = *n.parameters;
  if (n.physics_left_out) details["physics_left_out"] = {{"columns", n.physics_left_out->columns}, {"note", n.physics_left_out->note}};
  if (!n.data_share.empty()) {
    nlohmann::json share = nlohmann::json::object();
    for (const auto& [group, value] : n.data_share) share[group] = value;
    details["data_share"] = share;
  }
  if (const auto& ps = n.predictive_sigma) {
    details["predictive_sigma"] = {{"grid", "surface nodes"}, {"rms_dph", ps->rms_dph}, {"max_dph", ps->max_dph},
                                   {"max_at_temp_c", ps->max_at_temp_c}, {"max_at_rate_dps", ps->max_at_rate_dps}};
  }
  if (!n.physics_note.empty()) details["physics_note"] = n.physics_note;
  if (!n.noise_choice.empty()) details["noise_choice"] = n.noise_choice;
  if (!n.noise_identification.empty()) details["noise_identification"] = n.noise_identification;
  if (n.ridge_lambda) details["lambda"] = *n.ridge_lambda;
}

FitNotes fit_notes_of(const nlohmann::json& details) {
  FitNotes n;
  if (!details.is_object()) return n;
  const auto text = [&](const char* key) { return details.contains(key) ? details.at(key).get<std::string>() : std::string(); };
  if (details.contains("nodes")) n.nodes = details.at("nodes").get<int>();
  if (details.contains("parameters")) n.parameters = details.at("parameters").get<int>();
  if (details.contains("physics_left_out")) {
    const nlohmann::json& p = details.at("physics_left_out");
    n.physics_left_out = PhysicsLeftOut{p.at("columns").get<std::vector<std::string>>(), p.at("note").get<std::string>()};
  }
  if (details.contains("data_share")) {
    for (const auto& [group, share] : details.at("data_share").items()) n.data_share.emplace_back(group, share.get<double>());
  }
  if (details.contains("predictive_sigma")) {
    const nlohmann::json& p = details.at("predictive_sigma");
    n.predictive_sigma = PredictiveSigma{p.at("rms_dph").get<double>(), p.at("max_dph").get<double>(), p.at("max_at_temp_c").get<double>(),
                                         p.at("max_at_rate_dps").get<double>()};
  }
  n.physics_note = text("physics_note");
  n.noise_choice = text("noise_choice");
  n.noise_identification = text("noise_identification");
  if (details.contains("lambda") && details.at("lambda").is_number()) n.ridge_lambda = details.at("lambda").get<double>();
  return n;
}

}  // namespace gyrosid
