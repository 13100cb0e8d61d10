#include "loader.hpp"

#include <vector>  // before boost/dll (GCC 12 needs it for library_info)
#include <algorithm>
#include <cstdlib>
#include <sstream>

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

namespace gdsmc::host {

namespace fs = std::filesystem;

LoadedPlugin load_plugin(const fs::path& file) {
  LoadedPlugin p;
  p.file = file;
  auto lib = std::make_shared<boost::dll::shared_library>();
  try {
    // rtld_now: a missing symbol fails here, not on first call; local: no symbol leaks between plugins.
    lib->load(file, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    throw PluginLoadError(file.string() + ": cannot be loaded as a shared library: " + e.what());
  }
  if (!lib->has(plugin_entry_symbol))
    throw PluginLoadError(file.string() + ": not a gdsmc plugin (it exports no '" + plugin_entry_symbol +
                          "'); a plugin is built against the gdsmc SDK and registered with GDSMC_PLUGIN(...)");
  const PluginEntry* entry = nullptr;
  try {
    entry = lib->get_alias<const PluginEntry*()>(plugin_entry_symbol)();
  } catch (const std::exception& e) {
    throw PluginLoadError(file.string() + ": its plugin entry point failed: " + e.what());
  }
  if (!entry || entry->magic != plugin_magic)
    throw PluginLoadError(file.string() + ": not a gdsmc plugin (its entry point does not return a gdsmc plugin entry)");
  p.abi_major = entry->abi_major;
  p.abi_minor = entry->abi_minor;
  std::ostringstream versions;
  versions << "plugin SDK ABI " << entry->abi_major << "." << entry->abi_minor << ", host SDK ABI "
           << sdk_abi_major << "." << sdk_abi_minor;
  if (entry->abi_major != sdk_abi_major)
    throw PluginLoadError(file.string() + ": built against an incompatible gdsmc SDK (" + versions.str() +
                          "); rebuild the plugin against this gdsmc's SDK");
  if (entry->abi_minor > sdk_abi_minor)
    throw PluginLoadError(file.string() + ": built against a newer gdsmc SDK than this host (" + versions.str() +
                          "); upgrade gdsmc or rebuild the plugin against this SDK");
  if (entry->fingerprint != abi_fingerprint())
    throw PluginLoadError(file.string() + ": built with a different compiler, standard library or SDK layout (" +
                          versions.str() + ", layout fingerprints differ); rebuild it with this toolchain");
  try {
    p.descriptor = entry->describe();
  } catch (const std::exception& e) {
    throw PluginLoadError(file.string() + ": its descriptor threw: " + e.what());
  }
  if (!p.descriptor || p.descriptor->name.empty() || !p.descriptor->create)
    throw PluginLoadError(file.string() + ": its descriptor is incomplete (no name or no factory)");
  p.library = std::move(lib);
  return p;
}

void PluginRegistry::add(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(path, ec))
      if (e.is_regular_file() && e.path().extension() == ".so") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) add_file(f, false);
  } else if (fs::is_regular_file(path, ec)) {
    add_file(path, true);
  } else {
    warnings_.push_back(path.string() + ": plugin search path entry does not exist");
  }
}

void PluginRegistry::add_file(const fs::path& file, bool explicit_file) {
  const fs::path canon = fs::weakly_canonical(file);
  if (std::find(seen_.begin(), seen_.end(), canon) != seen_.end()) return;
  seen_.push_back(canon);
  LoadedPlugin p;
  try {
    p = load_plugin(file);
  } catch (const PluginLoadError& e) {
    if (explicit_file) throw;
    warnings_.push_back(e.what());
    return;
  }
  const std::string& name = p.descriptor->name;
  if (auto it = by_name_.find(name); it != by_name_.end()) {
    warnings_.push_back(file.string() + ": plugin '" + name + "' is shadowed by " + plugins_[it->second].file.string());
    return;
  }
  by_name_[name] = plugins_.size();
  plugins_.push_back(std::move(p));
}

std::vector<fs::path> PluginRegistry::default_search_path() {
  std::vector<fs::path> path;
  if (const char* env = std::getenv("GDSMC_PLUGIN_PATH")) {
    std::string s(env);
    std::size_t start = 0;
    while (start <= s.size()) {
      const std::size_t end = s.find(':', start);
      const std::string part = s.substr(start, end == std::string::npos ? std::string::npos : end - start);
      if (!part.empty()) path.emplace_back(part);
      if (end == std::string::npos) break;
      start = end + 1;
    }
  }
  std::error_code ec;
  const fs::path exe_dir = boost::dll::program_location(ec).parent_path();
  if (!ec) {
    for (const fs::path& candidate : {exe_dir / "plugins", exe_dir.parent_path() / "lib" / "gdsmc" / "plugins"})
      if (fs::is_directory(candidate)) path.push_back(candidate);
  }
  return path;
}

const LoadedPlugin* PluginRegistry::find(const std::string& name) const {
  auto it = by_name_.find(name);
  return it == by_name_.end() ? nullptr : &plugins_[it->second];
}

std::vector<std::string> PluginRegistry::names() const {
  std::vector<std::string> n;
  for (const auto& p : plugins_) n.push_back(p.descriptor->name);
  return n;
}

std::vector<std::string> PluginRegistry::names_of_kind(PluginKind kind) const {
  std::vector<std::string> n;
  for (const auto& p : plugins_)
    if (p.descriptor->kind == kind) n.push_back(p.descriptor->name);
  return n;
}

std::shared_ptr<PluginObject> create_object(const LoadedPlugin& plugin, const Params& params) {
  PluginObject* raw = plugin.descriptor->create(params);
  if (!raw) throw std::runtime_error("plugin '" + plugin.descriptor->name + "' factory returned nothing");
  auto library = plugin.library;
  // The deleter holds the library: it is unloaded (if ever) only after the object is gone.
  return std::shared_ptr<PluginObject>(raw, [library](PluginObject* o) { delete o; });
}

}  // namespace gdsmc::host
