// Deliberately broken (conformance test): exports a plugin entry that claims a future SDK ABI
// major version. `gdsmc conformance` must report abi_version FAIL (before reading anything else).
#include <gdsmc/gdsmc.hpp>

namespace {
struct WrongAbiRule {
  static constexpr const char* name = "conformance_wrong_abi";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: built for another SDK ABI major version";
  static constexpr const char* documentation = "Claims SDK ABI major + 1.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit WrongAbiRule(const gdsmc::Params&) {}
  double collide(gdsmc::Vec3&, gdsmc::Vec3&, const gdsmc::Vec3&, gdsmc::PairContext&) const { return 0.0; }
};

const gdsmc::PluginDescriptor* describe_wrong_abi() {
  static const gdsmc::PluginDescriptor d = gdsmc::describe<WrongAbiRule>();
  return &d;
}
const gdsmc::PluginEntry* wrong_abi_entry() {
  static const gdsmc::PluginEntry e{gdsmc::plugin_magic, GDSMC_SDK_ABI_MAJOR + 1, 0u, 0u, gdsmc::abi_fingerprint(),
                                    &describe_wrong_abi};
  return &e;
}
}  // namespace

BOOST_DLL_ALIAS(wrong_abi_entry, gdsmc_plugin_entry)
