// Loading and checking one plugin binary (Boost.DLL): the single implementation of the entry,
// ABI and fingerprint checks (the registry and `gdsmc conformance` both use it), and making
// objects that keep their library loaded.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gdsmc/plugin.hpp>

namespace boost::dll {
class shared_library;
}

namespace gdsmc::host {

// Thrown when a file cannot be used as a plugin; the message names the file and what to do.
class PluginLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LoadedPlugin {
  std::filesystem::path file;
  std::shared_ptr<boost::dll::shared_library> library;
  const PluginDescriptor* descriptor = nullptr;
  std::uint32_t abi_major = 0, abi_minor = 0;
  // The library file's content (util/content_hash.hpp), read when it was loaded: what identifies
  // the code that made a result (provenance, checkpoints), where the version string may not.
  std::uint64_t content_hash = 0;
};

// Load one shared library and check it is a gdsmc plugin of a compatible ABI. Nothing in the file
// is trusted: it is examined first (examine_libraries), and only loaded here if that went well.
// Throws PluginLoadError.
LoadedPlugin load_plugin(const std::filesystem::path& file);

// What a plugin says of itself, learnt without loading it in this process.
struct PluginInfo {
  std::filesystem::path file;
  std::string name;
  PluginKind kind = PluginKind::diagnostic;
  std::string version, summary;
  std::uint32_t abi_major = 0, abi_minor = 0;
};
struct Examined {
  PluginInfo info;    // file only, when error is set
  std::string error;  // the PluginLoadError message (names the file); empty if it may be loaded
};
// Examines each file without trusting it: the file itself (library_file_problem), then loading it
// in a forked child with a time limit (one child for all files, a new one after a crash), so a
// library that crashes, aborts or hangs when loaded (a static initialiser, a broken entry point)
// costs a warning, not the process.
std::vector<Examined> examine_libraries(const std::vector<std::filesystem::path>& files);
// Loads, in this process, a library examine_libraries accepted. Throws PluginLoadError.
LoadedPlugin load_examined(const PluginInfo& info);

// Why `file` cannot be a loadable shared library for this host, from the file alone ("" if it
// may be): a symbolic link loop, a directory, an empty or truncated file, no ELF header, another
// machine. dlopen of a truncated library crashes the process (SIGBUS) rather than failing.
std::string library_file_problem(const std::filesystem::path& file);

// The steps of load_plugin, each throwing PluginLoadError with a message that starts with the file.
// Open the library with every symbol resolved (rtld_now) and no symbol leaking to other plugins.
std::shared_ptr<boost::dll::shared_library> open_library(const std::filesystem::path& file);
// The library's plugin entry (exported symbol present, entry returned, magic number right).
const PluginEntry& plugin_entry(boost::dll::shared_library& lib, const std::filesystem::path& file);

// Whether an entry's ABI fits this host: `problem` is empty when it does.
struct AbiCheck {
  std::string versions;  // "plugin SDK ABI a.b, host SDK ABI c.d"
  std::string problem;   // what is wrong, e.g. "built against an incompatible gdsmc SDK"
  std::string remedy;    // what to do about it
};
AbiCheck check_abi(const PluginEntry& entry);

// Make an object with the plugin's factory. The returned pointer owns a reference to the library,
// so the library outlives every object made from it.
std::shared_ptr<PluginObject> create_object(const LoadedPlugin& plugin, const Params& params);

}  // namespace gdsmc::host
