#include "plugins/loader.hpp"

#include <vector>  // before boost/dll (GCC 12 needs it for library_info)
#include <sstream>

#include <boost/dll/shared_library.hpp>

namespace gdsmc::host {

namespace fs = std::filesystem;

std::shared_ptr<boost::dll::shared_library> open_library(const fs::path& file) {
  auto lib = std::make_shared<boost::dll::shared_library>();
  try {
    // rtld_now: a missing symbol fails here, not on first call; local: no symbol leaks between plugins.
    lib->load(file, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    throw PluginLoadError(file.string() + ": cannot be loaded as a shared library: " + e.what());
  }
  return lib;
}

const PluginEntry& plugin_entry(boost::dll::shared_library& lib, const fs::path& file) {
  if (!lib.has(plugin_entry_symbol))
    throw PluginLoadError(file.string() + ": not a gdsmc plugin (it exports no '" + plugin_entry_symbol +
                          "'); a plugin is built against the gdsmc SDK and registered with GDSMC_PLUGIN(...)");
  const PluginEntry* entry = nullptr;
  try {
    entry = lib.get_alias<const PluginEntry*()>(plugin_entry_symbol)();
  } catch (const std::exception& e) {
    throw PluginLoadError(file.string() + ": its plugin entry point failed: " + e.what());
  }
  if (!entry || entry->magic != plugin_magic)
    throw PluginLoadError(file.string() + ": not a gdsmc plugin (its entry point does not return a gdsmc plugin entry)");
  return *entry;
}

AbiCheck check_abi(const PluginEntry& entry) {
  AbiCheck c;
  std::ostringstream versions;
  versions << "plugin SDK ABI " << entry.abi_major << "." << entry.abi_minor << ", host SDK ABI " << sdk_abi_major
           << "." << sdk_abi_minor;
  c.versions = versions.str();
  if (entry.abi_major != sdk_abi_major) {
    c.problem = "built against an incompatible gdsmc SDK";
    c.remedy = "rebuild the plugin against this gdsmc's SDK";
  } else if (entry.abi_minor > sdk_abi_minor) {
    c.problem = "built against a newer gdsmc SDK than this host";
    c.remedy = "upgrade gdsmc or rebuild the plugin against this SDK";
  } else if (entry.fingerprint != abi_fingerprint()) {
    c.problem = "built with a different compiler, standard library or SDK layout";
    c.versions += ", layout fingerprints differ";
    c.remedy = "rebuild it with this toolchain";
  }
  return c;
}

LoadedPlugin load_plugin(const fs::path& file) {
  LoadedPlugin p;
  p.file = file;
  auto lib = open_library(file);
  const PluginEntry& entry = plugin_entry(*lib, file);
  p.abi_major = entry.abi_major;
  p.abi_minor = entry.abi_minor;
  if (const AbiCheck abi = check_abi(entry); !abi.problem.empty())
    throw PluginLoadError(file.string() + ": " + abi.problem + " (" + abi.versions + "); " + abi.remedy);
  try {
    p.descriptor = entry.describe();
  } catch (const std::exception& e) {
    throw PluginLoadError(file.string() + ": its descriptor threw: " + e.what());
  }
  if (!p.descriptor || p.descriptor->name.empty() || !p.descriptor->create)
    throw PluginLoadError(file.string() + ": its descriptor is incomplete (no name or no factory)");
  p.library = std::move(lib);
  return p;
}

std::shared_ptr<PluginObject> create_object(const LoadedPlugin& plugin, const Params& params) {
  PluginObject* raw = plugin.descriptor->create(params);
  if (!raw) throw std::runtime_error("plugin '" + plugin.descriptor->name + "' factory returned nothing");
  auto library = plugin.library;
  // The deleter holds the library: it is unloaded (if ever) only after the object is gone.
  return std::shared_ptr<PluginObject>(raw, [library](PluginObject* o) { delete o; });
}

}  // namespace gdsmc::host
