// The entry point of GDSMC_PLUGIN written by hand, with abi_major = GDSMC_SDK_ABI_MAJOR + 1.
#include <cstdlib>

#include <gdsmc/gdsmc.hpp>

namespace {

// Never reached: the host must stop at the ABI check. Aborting makes a missing check loud.
const gdsmc::PluginDescriptor* describe_wrong_abi() { std::abort(); }

const gdsmc::PluginEntry* wrong_abi_entry() {
  static const gdsmc::PluginEntry entry{gdsmc::plugin_magic, GDSMC_SDK_ABI_MAJOR + 1, 0u, 0u,
                                        gdsmc::abi_fingerprint(), &describe_wrong_abi};
  return &entry;
}

}  // namespace

BOOST_DLL_ALIAS(wrong_abi_entry, gdsmc_plugin_entry)
