// The error a refused pipeline throws: every problem found, one message each.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace gdsmc::host {

class PipelineError : public std::runtime_error {
 public:
  // warnings: what was noticed before the errors (a plugin directory that does not exist, a plugin
  // shadowed by another file of its name), printed with them, since they often explain them.
  explicit PipelineError(std::vector<std::string> messages, std::vector<std::string> warnings = {});
  const std::vector<std::string>& messages() const { return messages_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  std::vector<std::string> messages_;
  std::vector<std::string> warnings_;
};

}  // namespace gdsmc::host
