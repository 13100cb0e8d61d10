#include "config/errors.hpp"

#include "util/text.hpp"

namespace gdsmc::host {

PipelineError::PipelineError(std::vector<std::string> messages, std::vector<std::string> warnings)
    : std::runtime_error(join(messages, "\n")), messages_(std::move(messages)), warnings_(std::move(warnings)) {}

}  // namespace gdsmc::host
