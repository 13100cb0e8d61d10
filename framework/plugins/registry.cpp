#include "plugins/registry.hpp"

#include <vector>  // before boost/dll (GCC 12 needs it for library_info)
#include <algorithm>
#include <cstdlib>

#include <boost/dll/runtime_symbol_info.hpp>

namespace gdsmc::host {

namespace fs = std::filesystem;

void PluginRegistry::add(const fs::path& path) {
  searched_.push_back(path);
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    // Every *.so entry, whatever it is (a directory, a broken link): each one that cannot be a
    // plugin gets a warning saying why, rather than crashing or being skipped without a word.
    std::vector<fs::path> files;
    fs::directory_iterator it(path, ec), end;
    for (; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".so") files.push_back(it->path());
    if (ec) warnings_.push_back(path.string() + ": cannot list this plugin directory (" + ec.message() + ")");
    std::sort(files.begin(), files.end());
    add_files(files, false);
  } else if (fs::status(path, ec).type() != fs::file_type::not_found) {
    add_files({path}, true);  // a file, or a link loop: its problem is an error
  } else {
    warnings_.push_back(path.string() + ": plugin search path entry does not exist");
  }
}

void PluginRegistry::add_files(const std::vector<fs::path>& candidates, bool explicit_file) {
  std::vector<fs::path> files;
  for (const auto& f : candidates) {
    std::error_code ec;
    fs::path canon = fs::weakly_canonical(f, ec);
    if (ec) canon = fs::absolute(f, ec);  // a link loop has no canonical path
    if (std::find(seen_.begin(), seen_.end(), canon) != seen_.end()) continue;
    seen_.push_back(canon);
    files.push_back(f);
  }
  for (Examined& e : examine_libraries(files)) {
    if (!e.error.empty()) {
      if (explicit_file) throw PluginLoadError(e.error);
      warnings_.push_back(e.error);
      continue;
    }
    if (auto it = by_name_.find(e.info.name); it != by_name_.end()) {
      warnings_.push_back(e.info.file.string() + ": plugin '" + e.info.name + "' is shadowed by " +
                          found_[it->second].file.string());
      continue;
    }
    by_name_[e.info.name] = found_.size();
    found_.push_back(std::move(e.info));
    plugins_.emplace_back();
  }
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

const LoadedPlugin& PluginRegistry::loaded(std::size_t k) const {
  if (!plugins_[k].descriptor) plugins_[k] = load_examined(found_[k]);
  return plugins_[k];
}

const LoadedPlugin* PluginRegistry::find(const std::string& name) const {
  auto it = by_name_.find(name);
  return it == by_name_.end() ? nullptr : &loaded(it->second);
}

const std::vector<LoadedPlugin>& PluginRegistry::plugins() const {
  for (std::size_t k = 0; k < found_.size(); ++k) (void)loaded(k);
  return plugins_;
}

std::vector<std::string> PluginRegistry::names() const {
  std::vector<std::string> n;
  for (const auto& p : found_) n.push_back(p.name);
  return n;
}

std::vector<std::string> PluginRegistry::names_of_kind(PluginKind kind) const {
  std::vector<std::string> n;
  for (const auto& p : found_)
    if (p.kind == kind) n.push_back(p.name);
  return n;
}

}  // namespace gdsmc::host
