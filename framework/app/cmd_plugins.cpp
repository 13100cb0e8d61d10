// `gdsmc plugins`: list the plugins found, or document the ones named.
#include <iostream>

#include "app/commands.hpp"
#include "config/suggest.hpp"
#include "config/units.hpp"
#include "plugins/kinds.hpp"
#include "plugins/registry.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

const char* const kPluginsHelp = R"(gdsmc plugins [NAME | FILE.so]... [--plugin-path P]...

Without arguments: every plugin found on the search path, by kind, with its version and a
one-line summary, and a warning for each file on the path that could not be used (and why: a
broken library, not a plugin, or shadowed by an earlier plugin of the same name).
With names or .so files: the full documentation of each, and every parameter with its type,
default, range and unit. A .so file is loaded and checked (ABI version, descriptor) first.

Options:
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  -h, --help             this text
)";

namespace {

void print_plugin_doc(const LoadedPlugin& lp) {
  const PluginDescriptor& d = *lp.descriptor;
  std::cout << d.name << " (" << to_string(d.kind) << " plugin, version " << d.version << ", SDK ABI " << lp.abi_major
            << "." << lp.abi_minor << ")\n  file: " << lp.file.string() << "\n  " << d.summary << "\n\n";
  std::string doc = d.documentation;
  std::size_t start = 0;
  while (start < doc.size()) {
    const auto end = doc.find('\n', start);
    std::cout << "  " << doc.substr(start, end == std::string::npos ? std::string::npos : end - start) << "\n";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  std::cout << "\n  parameters:" << (d.parameters.empty() ? " none" : "") << "\n";
  for (const auto& s : d.parameters) {
    std::cout << "    " << s.name << " (" << to_string(s.type) << ")";
    if (s.default_) std::cout << "  default " << value_text(*s.default_);
    else std::cout << "  required";
    const std::string r = s.range_text();
    if (!r.empty()) std::cout << "  range " << r;
    if (!s.dimension.dimensionless())
      std::cout << "  dimension " << to_string(s.dimension) << "  unit " << reference_unit(s.dimension)
                << " (or {value, unit}: reduced, or any product of powers of lambda0, sigma, tau0, T0, m)";
    std::cout << "\n        " << s.doc << "\n";
  }
  if (const PluginKindInfo* kind = find_kind(d.kind); kind && kind->writes_output)
    std::cout << "    (every diagnostic also takes: name, sample_every, record_every)\n";
  std::cout << "\n";
}

}  // namespace

int cmd_plugins(const Options& o) {
  PluginRegistry reg;
  std::vector<std::string> errors;
  for (const auto& pth : o.plugin_paths) {
    try { reg.add(pth); } catch (const PluginLoadError& e) { errors.push_back(e.what()); }
  }
  for (const auto& pth : PluginRegistry::default_search_path()) reg.add(pth);
  if (o.positional.empty()) {
    for (const PluginKindInfo& row : kPluginKinds) {
      const PluginKind kind = row.kind;
      std::cout << to_string(kind) << ":\n";
      bool any = false;
      for (const auto& info : reg.available())  // as examined: listing loads nothing into this process
        if (info.kind == kind) {
          any = true;
          std::cout << fmt("  %-32s %-8s %s", info.name.c_str(), info.version.c_str(), info.summary.c_str()) << "\n";
        }
      if (!any) std::cout << "  (none)\n";
    }
    std::cout << "\n`gdsmc plugins NAME` documents a plugin and its parameters.\n";
    for (const auto& w : reg.warnings()) std::cerr << "warning: " << w << "\n";
    for (const auto& e : errors) std::cerr << "error: " << e << "\n";
    return errors.empty() ? 0 : 1;
  }
  int status = errors.empty() ? 0 : 1;
  for (const auto& e : errors) std::cerr << "error: " << e << "\n";
  for (const auto& name : o.positional) {
    if (name.size() > 3 && name.substr(name.size() - 3) == ".so") {
      try {
        const LoadedPlugin lp = load_plugin(name);
        print_plugin_doc(lp);
      } catch (const PluginLoadError& e) {
        std::cerr << "error: " << e.what() << "\n";
        status = 1;
      }
      continue;
    }
    if (const LoadedPlugin* lp = reg.find(name)) {
      print_plugin_doc(*lp);
    } else {
      auto close = closest_names(name, reg.names());
      const std::string hint = join(close, ", ");
      std::cerr << "error: no plugin named '" << name << "'" << (hint.empty() ? "" : "; did you mean " + hint + "?")
                << " (`gdsmc plugins` lists them)\n";
      status = 1;
    }
  }
  return status;
}

}  // namespace gdsmc::host
