// The entry point of GDSMC_PLUGIN written by hand, with abi_major = 1: a plugin built against the
// old SDK 1.x, which an SDK 2 host must refuse ("built against an incompatible gdsmc SDK").
#include <cstdlib>

#include <gdsmc/gdsmc.hpp>

namespace {

// Never reached: the host must stop at the ABI check. Aborting makes a missing check loud.
const gdsmc::PluginDescriptor* describe_wrong_abi() { std::abort(); }

const gdsmc::PluginEntry* wrong_abi_entry() {
  static_assert(GDSMC_SDK_ABI_MAJOR != 1, "this plugin must claim an ABI major the host does not have");
  static const gdsmc::PluginEntry entry{gdsmc::plugin_magic, 1u, 0u, 0u, gdsmc::abi_fingerprint(), &describe_wrong_abi};
  return &entry;
}

}  // namespace

BOOST_DLL_ALIAS(wrong_abi_entry, gdsmc_plugin_entry)
