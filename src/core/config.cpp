#include "core/config.h"

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/format.h"

namespace gyrosid {

const std::map<std::string, std::string_view>& builtin_configs();  // generated at build time

namespace {

constexpr std::string_view kBuiltinPrefix = "builtin:";

std::string mark_text(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  if (m.line < 0) return "";
  return str_cat(":", m.line + 1, ":", m.column + 1);
}

}  // namespace

std::optional<std::string_view> builtin_config(const std::string& relative_path) {
  const auto& all = builtin_configs();
  auto it = all.find(relative_path);
  if (it == all.end()) return std::nullopt;
  return it->second;
}

std::vector<std::string> builtin_config_names() {
  std::vector<std::string> names;
  for (const auto& [name, text] : builtin_configs()) names.push_back(name);
  return names;
}

std::string config_text(const std::string& path) {
  if (path.rfind(kBuiltinPrefix, 0) == 0) {
    const std::string rel = path.substr(kBuiltinPrefix.size());
    auto text = builtin_config(rel);
    if (!text) {
      std::string names;
      for (const auto& n : builtin_config_names()) names += "\n  builtin:" + n;
      fail(path, ": no such built-in config; built-in configs are:", names);
    }
    return std::string(*text);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::string hint;
    const std::string prefix = "configs/";
    const auto pos = path.rfind(prefix);
    if (pos != std::string::npos && builtin_config(path.substr(pos + prefix.size()))) {
      hint = str_cat(" (the built-in copy is available as builtin:", path.substr(pos + prefix.size()), ")");
    }
    fail(path, ": cannot open config file", hint);
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

ConfigNode ConfigNode::load(const std::string& path) { return parse(config_text(path), path); }

namespace {

// Every key of every map in the document must be a plain scalar, once per map: YAML allows keys that are
// maps or lists ("? [a, b]: 1") and yaml-cpp allows repeated keys, but no gyrosid config means either. The
// walk is bounded: aliases can make a short text expand to an enormous tree ("billion laughs").
void check_keys(const YAML::Node& node, const std::string& source, int depth, long& budget) {
  if (depth > 64) fail(source, mark_text(node), ": the document nests deeper than 64 levels");
  if (--budget < 0) fail(source, ": the document expands to more than a million nodes (aliases?)");
  if (node.IsMap()) {
    std::vector<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) fail(source, mark_text(kv.first), ": a key must be a plain name, not a map or a list");
      const std::string key = kv.first.Scalar();
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) fail(source, mark_text(kv.first), ": key '", key, "' appears twice");
      seen.push_back(key);
      check_keys(kv.second, source, depth + 1, budget);
    }
  } else if (node.IsSequence()) {
    for (const auto& item : node) check_keys(item, source, depth + 1, budget);
  }
}

}  // namespace

ConfigNode ConfigNode::parse(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    fail(source, ":", e.mark.line + 1, ":", e.mark.column + 1, ": YAML syntax error: ", e.msg);
  } catch (const YAML::Exception& e) {
    fail(source, ": not a YAML document: ", e.what());
  }
  long budget = 1000000;
  check_keys(root, source, 0, budget);
  return ConfigNode(root, source, "");
}

std::string ConfigNode::child_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : str_cat(path_, ".", key);
}

std::string ConfigNode::where() const {
  return str_cat(source_, mark_text(node_), path_.empty() ? "" : " (" + path_ + ")");
}

std::string ConfigNode::where(std::string_view key) const {
  if (node_.IsMap() && node_[std::string(key)]) {
    return str_cat(source_, mark_text(node_[std::string(key)]), " (", child_path(key), ")");
  }
  return str_cat(source_, mark_text(node_), " (", child_path(key), ")");
}

bool ConfigNode::has(std::string_view key) const {
  return node_.IsMap() && node_[std::string(key)] && !node_[std::string(key)].IsNull();
}

ConfigNode ConfigNode::operator[](std::string_view key) const {
  if (!node_.IsMap()) fail(where(), ": expected a map with key '", key, "'");
  YAML::Node child = node_[std::string(key)];
  if (!child || child.IsNull()) fail(where(key), ": missing required key '", key, "'");
  return ConfigNode(child, source_, child_path(key));
}

std::optional<ConfigNode> ConfigNode::find(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return ConfigNode(node_[std::string(key)], source_, child_path(key));
}

std::vector<std::string> ConfigNode::keys() const {
  std::vector<std::string> out;
  if (!node_.IsMap()) return out;
  for (const auto& kv : node_) out.push_back(kv.first.Scalar());
  return out;
}

void ConfigNode::allow_only(std::initializer_list<std::string_view> allowed) const {
  allow_only(std::vector<std::string>(allowed.begin(), allowed.end()));
}

void ConfigNode::allow_only(const std::vector<std::string>& allowed) const {
  if (node_.IsNull()) return;
  if (!node_.IsMap()) fail(where(), ": expected a map");
  for (const auto& kv : node_) {
    const std::string key = kv.first.Scalar();
    bool ok = false;
    for (const auto& a : allowed) ok = ok || a == key;
    if (!ok) fail(source_, mark_text(kv.first), " (", child_path(key), "): unknown key '", key, "'; allowed here: ", join(allowed));
  }
}

ConfigNode ConfigNode::at(std::size_t index) const {
  if (!node_.IsSequence()) fail(where(), ": expected a list");
  if (index >= node_.size()) fail(where(), ": index ", index, " out of range");
  return ConfigNode(node_[index], source_, str_cat(path_, "[", index, "]"));
}

double ConfigNode::as_number() const {
  if (!node_.IsScalar()) fail(where(), ": expected a number");
  try {
    return node_.as<double>();
  } catch (const YAML::Exception&) {
    fail(where(), ": expected a number, found '", node_.Scalar(), "'");
  }
}

int ConfigNode::as_integer() const {
  if (!node_.IsScalar()) fail(where(), ": expected an integer");
  try {
    return node_.as<int>();  // yaml-cpp refuses text, fractions and values outside int's range
  } catch (const YAML::Exception&) {
    fail(where(), ": expected an integer (at most ", std::numeric_limits<int>::max(), " in magnitude), found '", node_.Scalar(), "'");
  }
}

std::string ConfigNode::as_text() const {
  if (!node_.IsScalar()) fail(where(), ": expected a text value");
  return node_.Scalar();
}

std::vector<double> ConfigNode::as_numbers() const {
  if (node_.IsScalar()) return {as_number()};
  if (!node_.IsSequence()) fail(where(), ": expected a list of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(at(i).as_number());
  return out;
}

std::vector<int> ConfigNode::as_integers() const {
  if (node_.IsScalar()) return {as_integer()};
  if (!node_.IsSequence()) fail(where(), ": expected a list of integers");
  std::vector<int> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(at(i).as_integer());
  return out;
}

std::vector<std::vector<double>> ConfigNode::as_matrix() const {
  if (!node_.IsSequence()) fail(where(), ": expected a list of rows");
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < node_.size(); ++i) {
    rows.push_back(at(i).as_numbers());
    if (rows.back().size() != rows.front().size()) {
      fail(at(i).where(), ": row has ", rows.back().size(), " values, the first row has ", rows.front().size());
    }
  }
  return rows;
}

double ConfigNode::number(std::string_view key) const { return (*this)[key].as_number(); }
double ConfigNode::number(std::string_view key, double fallback) const {
  return has(key) ? (*this)[key].as_number() : fallback;
}
int ConfigNode::integer(std::string_view key) const { return (*this)[key].as_integer(); }
int ConfigNode::integer(std::string_view key, int fallback) const {
  return has(key) ? (*this)[key].as_integer() : fallback;
}
std::string ConfigNode::text(std::string_view key) const { return (*this)[key].as_text(); }
std::string ConfigNode::text(std::string_view key, const std::string& fallback) const {
  return has(key) ? (*this)[key].as_text() : fallback;
}
bool ConfigNode::flag(std::string_view key, bool fallback) const {
  if (!has(key)) return fallback;
  ConfigNode child = (*this)[key];
  try {
    return child.node_.as<bool>();
  } catch (const YAML::Exception&) {
    fail(child.where(), ": expected true or false, found '", child.node_.Scalar(), "'");
  }
}
std::vector<double> ConfigNode::numbers(std::string_view key) const { return (*this)[key].as_numbers(); }
std::vector<double> ConfigNode::numbers(std::string_view key, const std::vector<double>& fallback) const {
  return has(key) ? (*this)[key].as_numbers() : fallback;
}

std::vector<int> ConfigNode::integers(std::string_view key, const std::vector<int>& fallback) const {
  return has(key) ? (*this)[key].as_integers() : fallback;
}

std::string ConfigNode::resolve(const std::string& relative) const {
  if (relative.rfind(kBuiltinPrefix, 0) == 0 || std::filesystem::path(relative).is_absolute()) return relative;
  if (source_.rfind(kBuiltinPrefix, 0) == 0) {
    const std::filesystem::path base = std::filesystem::path(source_.substr(kBuiltinPrefix.size())).parent_path();
    return std::string(kBuiltinPrefix) + (base / relative).lexically_normal().generic_string();
  }
  return (std::filesystem::path(source_).parent_path() / relative).lexically_normal().string();
}

}  // namespace gyrosid
