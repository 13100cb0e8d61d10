#include "config/errors.hpp"

#include "util/text.hpp"

namespace gdsmc::host {

PipelineError::PipelineError(std::vector<std::string> messages)
    : std::runtime_error(join(messages, "\n")), messages_(std::move(messages)) {}

}  // namespace gdsmc::host
