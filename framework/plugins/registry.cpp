#include "plugins/registry.hpp"

#include <vector>  // before boost/dll (GCC 12 needs it for library_info)
#include <algorithm>
#include <cstdlib>

#include <boost/dll/runtime_symbol_info.hpp>

namespace gdsmc::host {

namespace fs = std::filesystem;

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

}  // namespace gdsmc::host
