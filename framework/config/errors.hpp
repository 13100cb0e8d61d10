// The error a refused pipeline throws: every problem found, each as a structured ConfigError
// (where, which key, which plugin and parameter, what is wrong, what would be valid) and as the
// line printed for it.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace gdsmc::host {

// Who found the problem: the host's checks of the pipeline, or the plugin itself when it was built
// with the entry's values (its constructor threw a ParameterError, or failed otherwise).
enum class ErrorOrigin { host_check, refused_by_plugin, plugin_failed };

struct ConfigError {
  std::string location;   // "file:line:column", "--set KEY=VALUE", a sweep entry; empty: the whole input
  std::string path;       // the key, e.g. "collision.alpha", "diagnostics[1].every"; empty: none
  std::string plugin;     // the plugin the entry names, when the problem is about a plugin's entry
  std::string parameter;  // the plugin's parameter, when the problem is about one
  std::string message;    // what is wrong
  std::string valid;      // what would be valid, when the check knows it ("[0, 1]"); may be empty
  ErrorOrigin origin = ErrorOrigin::host_check;
  // The cases of a sweep it occurs in ("in sweep case 1 (collision.alpha=1.5)", "in all 4 sweep
  // cases"); empty: not a sweep, or a problem found before the cases.
  std::string sweep_cases;

  // "location: path: message; valid: ...; sweep cases" -- the line `validate` and `run` print.
  std::string text() const;
};

class PipelineError : public std::runtime_error {
 public:
  // warnings: what was noticed before the errors (a plugin directory that does not exist, a plugin
  // shadowed by another file of its name), printed with them, since they often explain them.
  explicit PipelineError(std::vector<ConfigError> errors, std::vector<std::string> warnings = {});
  // Problems of the whole input (an unreadable file, malformed YAML, a sweep too large), each
  // already a whole line.
  explicit PipelineError(const std::vector<std::string>& messages, std::vector<std::string> warnings = {});
  const std::vector<ConfigError>& errors() const { return errors_; }
  const std::vector<std::string>& messages() const { return messages_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  std::vector<ConfigError> errors_;
  std::vector<std::string> messages_;  // errors_[k].text()
  std::vector<std::string> warnings_;
};

}  // namespace gdsmc::host
