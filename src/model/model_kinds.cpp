#include "model/model_kinds.h"

#include "model/classical_model.h"
#include "model/explained_model.h"
#include "model/greybox_model.h"
#include "model/hybrid_model.h"
#include "model/rbf_network.h"
#include "model/triad_model.h"

namespace gyrosid {

ModelTarget ModelFile::target() const { return parse_enum<ModelTarget>(json.at("target").get<std::string>(), source); }

const ModelKindRegistry& model_kinds() { return extend_model_kinds(); }

ModelKindRegistry& extend_model_kinds() {
  static ModelKindRegistry registry = [] {
    ModelKindRegistry r("model kind");
    auto none = [] { return std::string(); };
    r.add({"rbf", "Gaussian RBF network with a width per input per node (thesis eqs 4.1-4.5)", none,
           [](const ModelFile& f) -> std::unique_ptr<SensorModel> { return RbfNetwork::from_json(f.parameters(), f.features(), f.target()); }})
        .add({"classical", "bias and scale-factor polynomials of the industry calibration (thesis s5.3.2)", none,
              [](const ModelFile& f) -> std::unique_ptr<SensorModel> { return ClassicalModel::from_json(f.parameters(), f.features(), f.target()); }})
        .add({"greybox", "the unified sensor model (thesis eq 3.48) with estimated coefficients", none,
              [](const ModelFile& f) -> std::unique_ptr<SensorModel> { return GreyboxModel::from_json(f.parameters(), f.features(), f.target()); }})
        .add({"explained", "a prior model plus the physics terms explain found or re-estimated", none,
              [](const ModelFile& f) -> std::unique_ptr<SensorModel> { return ExplainedModel::from_json(f.parameters(), f.source); }})
        .add({"hybrid", "grey-box physics terms plus an RBF network on what they leave, with a joint posterior (issue 11)", none,
              [](const ModelFile& f) -> std::unique_ptr<SensorModel> {
                return HybridModel::from_json(f.parameters(), f.features(), f.target(), f.source);
              }})
        .add({"triad", "a gyro triad: misalignment (thesis eq 3.72), bias b(T), g-sensitivity and a surface per gyro", none,
              [](const ModelFile& f) -> std::unique_ptr<SensorModel> { return std::make_unique<TriadModel>(triad_model_from_json(f.json, f.source)); }});
    return r;
  }();
  return registry;
}

}  // namespace gyrosid
