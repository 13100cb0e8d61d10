// Deliberately broken (conformance test): exports a plugin entry that claims the old SDK ABI
// major version 1 (a plugin built against SDK 1.x). `gdsmc conformance` must report abi_version
// FAIL (before reading anything else).
#include <gdsmc/gdsmc.hpp>

namespace {
struct WrongAbiRule {
  static constexpr const char* name = "conformance_wrong_abi";
  static constexpr const char* version = "0.0.1";
  static constexpr const char* summary = "Test plugin: built for another SDK ABI major version";
  static constexpr const char* documentation = "Claims SDK ABI 1.0, the major before SDK 2.0.";
  static std::vector<gdsmc::ParamSpec> parameters() { return {}; }
  explicit WrongAbiRule(const gdsmc::Params&) {}
  double collide(gdsmc::Vec3&, gdsmc::Vec3&, const gdsmc::Vec3&, gdsmc::PairContext&) const { return 0.0; }
};

const gdsmc::PluginDescriptor* describe_wrong_abi() {
  static const gdsmc::PluginDescriptor d = gdsmc::describe<WrongAbiRule>();
  return &d;
}
const gdsmc::PluginEntry* wrong_abi_entry() {
  static_assert(GDSMC_SDK_ABI_MAJOR != 1, "this plugin must claim an ABI major the host does not have");
  static const gdsmc::PluginEntry e{gdsmc::plugin_magic, 1u, 0u, 0u, gdsmc::abi_fingerprint(), &describe_wrong_abi};
  return &e;
}
}  // namespace

BOOST_DLL_ALIAS(wrong_abi_entry, gdsmc_plugin_entry)
