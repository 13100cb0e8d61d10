// Reading a YAML pipeline: typed readers and key checks that record every problem with its
// location (file:line:column, or the --set assignment that gave the value).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include <gdsmc/params.hpp>

#include "config/errors.hpp"

namespace gdsmc::host {

// A pipeline is a small text file: anything that is not a regular file, or is larger than this,
// is refused before it is read (`validate /dev/zero` would otherwise read until memory runs out).
inline constexpr std::uintmax_t kMaxPipelineBytes = 16u << 20;

// The text of a pipeline file; throws PipelineError naming the file and why it cannot be read.
std::string read_pipeline_text(const std::filesystem::path& file);

// Reads a YAML document and records every problem with its location.
class Checker {
 public:
  // `overrides`: the --set assignments; `from_sweep`: the assignments a sweep case applied after
  // them, each with its entry in the sweep.
  Checker(std::filesystem::path file, std::vector<std::string> overrides,
          std::vector<std::pair<std::string, SourceLocation>> from_sweep = {})
      : file_(std::move(file)), overrides_(std::move(overrides)), from_sweep_(std::move(from_sweep)) {}

  // Where the value at `path` came from: the sweep entry or the --set assignment that gave it
  // (the last applied first), else the node's mark.
  SourceLocation where(const std::string& path, const YAML::Node& node) const;
  // Record a problem at `path`; `valid` says what would be valid, when known. The error names the
  // plugin and parameter of the innermost About alive (a plugin's entry being read).
  void error(const SourceLocation& at, const std::string& path, const std::string& message,
             const std::string& valid = "");
  void error(const std::string& path, const YAML::Node& node, const std::string& message,
             const std::string& valid = "");
  // A problem the plugin itself reported (origin refused_by_plugin or plugin_failed).
  void plugin_error(const SourceLocation& at, const std::string& path, ErrorOrigin origin, const std::string& message);
  const std::vector<ConfigError>& errors() const { return errors_; }
  // A problem that does not refuse the pipeline but that the user should see (a missing
  // `plugins:` directory, a time step that crosses the slab's gap): the whole line, located.
  void warn(std::string line) { warnings_.push_back(std::move(line)); }
  const std::vector<std::string>& warnings() const { return warnings_; }

  // While an About lives, the errors recorded concern `plugin` (and its `parameter`, when given).
  class About {
   public:
    About(Checker& c, const std::string& plugin, const std::string& parameter = "");
    ~About();
    About(const About&) = delete;
    About& operator=(const About&) = delete;

   private:
    Checker& c_;
    std::string plugin_, parameter_;
  };

  // Report keys not in `allowed` (with close spellings) and duplicate keys; false if a key is not in `allowed`.
  bool check_keys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& allowed);

  // Typed readers: the value, or nullopt after recording an error.
  std::optional<double> real(const YAML::Node& n, const std::string& path);
  std::optional<std::int64_t> integer(const YAML::Node& n, const std::string& path);
  std::optional<bool> boolean(const YAML::Node& n, const std::string& path);
  static std::string describe(const YAML::Node& n);

 private:
  std::filesystem::path file_;
  std::vector<std::string> overrides_;
  std::vector<std::pair<std::string, SourceLocation>> from_sweep_;
  std::vector<ConfigError> errors_;
  std::vector<std::string> warnings_;
  std::string plugin_, parameter_;  // of the innermost About
};

// Canonical path of a list item: item("diagnostics", 1) == "diagnostics[1]".
inline std::string item(const std::string& path, std::size_t k) { return path + "[" + std::to_string(k) + "]"; }

}  // namespace gdsmc::host
