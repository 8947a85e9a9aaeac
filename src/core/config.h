// YAML configuration access with errors that name the file, the line and the key path.
//
//   ConfigNode sensor = ConfigNode::load("configs/sensors/open_loop_fog.yaml");
//   sensor.allow_only({"kind", "name", "bias", "scale_factor", "noise"});
//   double b = sensor["bias"].number("constant_dph", 0.0);
//
// A path "builtin:sensors/open_loop_fog.yaml" reads the copy of configs/ embedded in the library.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gyrosid {

class ConfigNode {
 public:
  static ConfigNode load(const std::string& path);
  static ConfigNode parse(const std::string& text, const std::string& source);

  // Children of a map. operator[] requires the key; find() returns nullopt when absent or null.
  bool has(std::string_view key) const;
  ConfigNode operator[](std::string_view key) const;
  std::optional<ConfigNode> find(std::string_view key) const;
  std::vector<std::string> keys() const;
  // Rejects keys outside `allowed`, listing the allowed ones (catches typos in configs).
  void allow_only(std::initializer_list<std::string_view> allowed) const;
  void allow_only(const std::vector<std::string>& allowed) const;

  // Typed values of children; the one-argument forms require the key.
  double number(std::string_view key) const;
  double number(std::string_view key, double fallback) const;
  int integer(std::string_view key) const;  // whole numbers within int's range
  int integer(std::string_view key, int fallback) const;
  std::string text(std::string_view key) const;
  std::string text(std::string_view key, const std::string& fallback) const;
  bool flag(std::string_view key, bool fallback) const;
  std::vector<double> numbers(std::string_view key) const;
  std::vector<double> numbers(std::string_view key, const std::vector<double>& fallback) const;
  std::vector<int> integers(std::string_view key, const std::vector<int>& fallback) const;

  // This node's own value.
  double as_number() const;
  int as_integer() const;
  std::string as_text() const;
  std::vector<double> as_numbers() const;
  std::vector<int> as_integers() const;
  std::vector<std::vector<double>> as_matrix() const;  // sequence of equal-length sequences

  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }
  std::size_t size() const { return node_.size(); }
  ConfigNode at(std::size_t index) const;

  // "file.yaml:12:3 (bias.constant_dph)" - for error messages.
  std::string where() const;
  std::string where(std::string_view key) const;
  const std::string& source() const { return source_; }
  const std::string& key_path() const { return path_; }
  // A path written in this config, resolved against the config's own directory (or builtin tree).
  std::string resolve(const std::string& relative) const;

 private:
  ConfigNode(YAML::Node node, std::string source, std::string path)
      : node_(std::move(node)), source_(std::move(source)), path_(std::move(path)) {}
  std::string child_path(std::string_view key) const;

  YAML::Node node_;
  std::string source_;
  std::string path_;
};

// The text of a config file, or of a built-in config "builtin:<relative path>"; Error naming the path.
std::string config_text(const std::string& path);

// Text of a config embedded from configs/ (relative path like "sensors/open_loop_fog.yaml"), or nullopt.
std::optional<std::string_view> builtin_config(const std::string& relative_path);
std::vector<std::string> builtin_config_names();

}  // namespace gyrosid
