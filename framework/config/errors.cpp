#include "config/errors.hpp"

#include "util/text.hpp"

namespace gdsmc::host {

std::string ConfigError::text() const {
  return (location.empty() ? "" : location + ": ") + (path.empty() ? "" : path + ": ") + message +
         (valid.empty() ? "" : "; valid: " + valid) + (sweep_cases.empty() ? "" : "; " + sweep_cases);
}

namespace {
std::vector<std::string> texts(const std::vector<ConfigError>& errors) {
  std::vector<std::string> out;
  for (const auto& e : errors) out.push_back(e.text());
  return out;
}
std::vector<ConfigError> whole_input(const std::vector<std::string>& messages) {
  std::vector<ConfigError> out;
  for (const auto& m : messages) out.push_back(ConfigError{"", "", "", "", m, "", ErrorOrigin::host_check, ""});
  return out;
}
}  // namespace

PipelineError::PipelineError(std::vector<ConfigError> errors, std::vector<std::string> warnings)
    : std::runtime_error(join(texts(errors), "\n")),
      errors_(std::move(errors)),
      messages_(texts(errors_)),
      warnings_(std::move(warnings)) {}

PipelineError::PipelineError(const std::vector<std::string>& messages, std::vector<std::string> warnings)
    : PipelineError(whole_input(messages), std::move(warnings)) {}

}  // namespace gdsmc::host
