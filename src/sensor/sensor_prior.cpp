#include "sensor/sensor_prior.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

#include "core/config.h"
#include "core/error.h"
#include "core/format.h"
#include "core/random.h"

namespace gyrosid {
namespace {

// One varied path of `draws.vary`: an additive normal draw (sd) or a log-normal factor (log_sd).
struct Variation {
  std::string path;
  double sd = 0.0, log_sd = 0.0;
  std::string where;  // the prior file's place, for errors
};

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t dot; (dot = path.find('.', start)) != std::string::npos; start = dot + 1) parts.push_back(path.substr(start, dot - start));
  parts.push_back(path.substr(start));
  return parts;
}

bool is_index(const std::string& s) { return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos; }

// Every number of `node` (a scalar, or nested lists of them) mapped by f, in place. False if one is not a number.
template <class F>
bool map_numbers(YAML::Node node, const F& f) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (!map_numbers(node[i], f)) return false;
    }
    return true;
  }
  double v = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v)) return false;
  node = format_number(f(v));  // reads back to the same double
  return true;
}

// The node at `parts` below `node` (handles share the tree: edits through it edit the document), or an undefined node.
YAML::Node descend(YAML::Node node, const std::vector<std::string>& parts, std::size_t k) {
  if (k == parts.size()) return node;
  if (node.IsSequence() && is_index(parts[k])) {
    const std::size_t i = std::stoul(parts[k]);
    return i < node.size() ? descend(node[i], parts, k + 1) : YAML::Node(YAML::NodeType::Undefined);
  }
  const YAML::Node& look = node;  // the const lookup adds no key
  if (!node.IsMap() || !look[parts[k]]) return YAML::Node(YAML::NodeType::Undefined);
  return descend(node[parts[k]], parts, k + 1);
}

std::vector<Variation> load_variations(const ConfigNode& vary) {
  std::vector<Variation> out;
  for (const std::string& path : vary.keys()) {
    const ConfigNode law = vary[path];
    law.allow_only({"sd", "log_sd"});
    Variation v{path, law.number("sd", 0.0), law.number("log_sd", 0.0), vary.where(path)};
    if (!(v.sd >= 0.0) || !(v.log_sd >= 0.0) || (v.sd > 0.0) == (v.log_sd > 0.0)) {
      fail(v.where, ": give exactly one of sd (additive) or log_sd (a factor exp(N(0, log_sd^2))), positive");
    }
    out.push_back(std::move(v));
  }
  return out;
}

// The member `parent` (its config text `text`, read from `origin`) with every variation drawn once.
SensorPriorMember draw_member(const SensorPriorMember& parent, const std::string& text, const std::vector<Variation>& vary,
                              std::uint64_t seed, std::size_t parent_index, int j) {
  YAML::Node doc = YAML::Load(text);
  for (const Variation& v : vary) {
    YAML::Node target = descend(doc, split_path(v.path), 0);
    RandomStream rng(seed, str_cat("prior/", parent_index, "/", j, "/", v.path));
    const double z = rng.normal();
    const bool ok = target.IsDefined() &&
                    map_numbers(target, [&](double x) { return v.sd > 0.0 ? x + v.sd * z : x * std::exp(v.log_sd * z); });
    if (!ok) fail(v.where, ": ", parent.origin, " has no number or list of numbers at '", v.path, "'");
  }
  SensorPriorMember m;
  m.name = str_cat(parent.name, " (draw ", j, ")");
  m.origin = str_cat(parent.origin, ", draw ", j);
  doc["name"] = m.name;
  YAML::Emitter out;
  out << doc;
  m.sensor = load_sensor(ConfigNode::parse(out.c_str(), m.origin));
  m.weight = parent.weight;
  return m;
}

// `count` members drawn around `parent` (its config text `text`) by the draws node of its list item.
void add_draws(const ConfigNode& draws, const SensorPriorMember& parent, const std::string& text, std::size_t parent_index,
               std::vector<SensorPriorMember>& out) {
  draws.allow_only({"count", "seed", "vary"});
  const int count = draws.integer("count");
  if (count < 1 || count > 10000) fail(draws.where("count"), ": between 1 and 10000 draws per member");
  const auto seed = static_cast<std::uint64_t>(draws.integer("seed", 1));
  const std::vector<Variation> vary = load_variations(draws["vary"]);
  for (int j = 1; j <= count; ++j) out.push_back(draw_member(parent, text, vary, seed, parent_index, j));
}

SensorPrior load_prior_node(const ConfigNode& root) {
  root.allow_only({"format", "name", "members", "population"});  // population: a lot's (lot/lot_model.h), read by the lot's commands
  if (const std::string f = root.text("format"); f != kSensorPriorFormat) fail(root.where("format"), ": expected '", kSensorPriorFormat, "', got '", f, "'");
  SensorPrior prior;
  prior.source = root.source();
  prior.name = root.text("name", root.source());
  const ConfigNode list = root["members"];
  if (!list.is_sequence() || list.size() == 0) fail(list.where(), ": members must be a non-empty list of {sensor: PATH, weight: W}");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const ConfigNode item = list.at(i);
    item.allow_only({"sensor", "weight", "draws"});
    SensorPriorMember m;
    m.weight = item.number("weight", 1.0);
    if (!(m.weight > 0.0) || !std::isfinite(m.weight)) fail(item.where("weight"), ": a member's weight must be positive");
    if (item["sensor"].is_map()) {  // an inline sensor config (a lot's members)
      if (item.has("draws")) fail(item.where("draws"), ": draws need the member's sensor config in a file");
      m.origin = item.where("sensor");
      m.sensor = load_sensor(item["sensor"]);
      m.name = sensor_name(m.sensor);
      prior.members.push_back(m);
      continue;
    }
    m.origin = item.resolve(item.text("sensor"));
    const std::string text = config_text(m.origin);
    m.sensor = load_sensor(ConfigNode::parse(text, m.origin));
    m.name = sensor_name(m.sensor);
    prior.members.push_back(m);
    if (const auto draws = item.find("draws")) add_draws(*draws, m, text, i, prior.members);
  }
  return prior;
}

}  // namespace

double SensorPrior::total_weight() const {
  double w = 0.0;
  for (const auto& m : members) w += m.weight;
  return w;
}

SensorPrior load_sensor_prior(const std::string& path) {
  const ConfigNode root = ConfigNode::load(path);
  if (root.has("format")) return load_prior_node(root);
  SensorPrior prior;  // a sensor config: the prior of that one sensor
  prior.source = path;
  prior.members.push_back({"", path, load_sensor(root), 1.0});
  prior.members.front().name = prior.name = sensor_name(prior.members.front().sensor);
  return prior;
}

}  // namespace gyrosid
