#include "model/model_kinds.h"

#include "model/classical_model.h"
#include "model/explained_model.h"
#include "model/greybox_model.h"
#include "model/hybrid_model.h"
#include "model/rbf_network.h"

namespace gyrosid {

const ModelKindRegistry& model_kinds() { return extend_model_kinds(); }

ModelKindRegistry& extend_model_kinds() {
  static ModelKindRegistry registry = [] {
    ModelKindRegistry r("model kind");
    auto none = [] { return std::string(); };
    r.add({"rbf", "Gaussian RBF network with a width per input per node (thesis eqs 4.1-4.5)", none,
           [](const ModelFile& f) -> std::unique_ptr<CalibrationModel> { return RbfNetwork::from_json(f.parameters, f.features, f.target); }})
        .add({"classical", "bias and scale-factor polynomials of the industry calibration (thesis s5.3.2)", none,
              [](const ModelFile& f) -> std::unique_ptr<CalibrationModel> { return ClassicalModel::from_json(f.parameters, f.features, f.target); }})
        .add({"greybox", "the unified sensor model (thesis eq 3.48) with estimated coefficients", none,
              [](const ModelFile& f) -> std::unique_ptr<CalibrationModel> { return GreyboxModel::from_json(f.parameters, f.features, f.target); }})
        .add({"explained", "a prior model plus the physics terms explain found or re-estimated", none,
              [](const ModelFile& f) -> std::unique_ptr<CalibrationModel> { return ExplainedModel::from_json(f.parameters, f.source); }})
        .add({"hybrid", "grey-box physics terms plus an RBF network on what they leave, with a joint posterior (issue 11)", none,
              [](const ModelFile& f) -> std::unique_ptr<CalibrationModel> {
                return HybridModel::from_json(f.parameters, f.features, f.target, f.source);
              }});
    return r;
  }();
  return registry;
}

}  // namespace gyrosid
