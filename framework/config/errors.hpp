// The error a refused pipeline throws: every problem found, one message each.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace gdsmc::host {

class PipelineError : public std::runtime_error {
 public:
  explicit PipelineError(std::vector<std::string> messages);
  const std::vector<std::string>& messages() const { return messages_; }

 private:
  std::vector<std::string> messages_;
};

}  // namespace gdsmc::host
