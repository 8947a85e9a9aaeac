// Recorded channels as regressors, as they are or squared: specific force (g- and g^2-sensitivity),
// magnetic field, the other axes' rates (cross-axis coupling), auxiliaries.
#include "core/error.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {

ChannelTerm::ChannelTerm(std::vector<std::string> channels, bool squared) : channels_(std::move(channels)), squared_(squared) {}

std::vector<std::string> ChannelTerm::column_names() const {
  if (!squared_) return channels_;
  std::vector<std::string> out;
  for (const auto& c : channels_) out.push_back(c + "^2");
  return out;
}

void ChannelTerm::columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const {
  for (std::size_t c = 0; c < channels_.size(); ++c) {
    const Eigen::VectorXd& v = in.signals.channel(channels_[c]);
    if (squared_) out.col(static_cast<Eigen::Index>(c)) = v.array().square().matrix();
    else out.col(static_cast<Eigen::Index>(c)) = v;
  }
}

std::string ChannelTerm::export_c(TermCode& code) const {
  for (std::size_t c = 0; c < channels_.size(); ++c) {
    const std::string x = code.input(channels_[c]);
    code.body << "  e += " << code.coefficient(static_cast<int>(c)) << " * " << x;
    if (squared_) code.body << " * " << x;
    code.body << ";\n";
  }
  return "";
}

Term channel_term(std::vector<std::string> channels, bool squared) {
  return Term(std::make_shared<ChannelTerm>(std::move(channels), squared));
}

}  // namespace gyrosid
