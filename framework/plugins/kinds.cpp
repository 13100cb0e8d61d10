#include "plugins/kinds.hpp"

#include <stdexcept>

namespace gdsmc::host {

const PluginKindInfo* find_kind(PluginKind kind) {
  for (const PluginKindInfo& k : kPluginKinds)
    if (k.kind == kind) return &k;
  return nullptr;
}

const PluginKindInfo& kind_info(PluginKind kind) {
  if (const PluginKindInfo* k = find_kind(kind)) return *k;
  throw std::logic_error("plugin kind " + std::to_string(static_cast<unsigned>(kind)) + " has no row in kPluginKinds");
}

const std::vector<std::string>& reserved_keys(PluginKind kind) {
  static const std::vector<std::string> output = {"plugin", "name", "sample_every", "record_every"};
  static const std::vector<std::string> other = {"plugin", "name"};
  return kind_info(kind).writes_output ? output : other;
}

const std::vector<std::string>& all_reserved_keys() { return reserved_keys(PluginKind::diagnostic); }

}  // namespace gdsmc::host
