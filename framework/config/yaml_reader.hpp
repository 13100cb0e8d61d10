// Reading a YAML pipeline: typed readers and key checks that record every problem with its
// location (file:line:column, or the --set assignment that gave the value).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include <gdsmc/params.hpp>

namespace gdsmc::host {

// Reads a YAML document and records every problem with its location.
class Checker {
 public:
  Checker(std::filesystem::path file, std::vector<std::string> overrides)
      : file_(std::move(file)), overrides_(std::move(overrides)) {}

  // Where the value at `path` came from: the --set assignment that gave it, else the node's mark.
  SourceLocation where(const std::string& path, const YAML::Node& node) const;
  void error(const SourceLocation& at, const std::string& path, const std::string& message);
  void error(const std::string& path, const YAML::Node& node, const std::string& message);
  const std::vector<std::string>& errors() const { return errors_; }

  // Report keys not in `allowed` (with close spellings) and duplicate keys.
  void check_keys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& allowed);

  // Typed readers: the value, or nullopt after recording an error.
  std::optional<double> real(const YAML::Node& n, const std::string& path);
  std::optional<std::int64_t> integer(const YAML::Node& n, const std::string& path);
  std::optional<bool> boolean(const YAML::Node& n, const std::string& path);
  static std::string describe(const YAML::Node& n);

 private:
  std::filesystem::path file_;
  std::vector<std::string> overrides_;
  std::vector<std::string> errors_;
};

// Canonical path of a list item: item("diagnostics", 1) == "diagnostics[1]".
inline std::string item(const std::string& path, std::size_t k) { return path + "[" + std::to_string(k) + "]"; }

}  // namespace gdsmc::host
