#include "plugins/loader.hpp"

#include "util/content_hash.hpp"

#include <elf.h>
#include <fcntl.h>
#include <link.h>
#include <sys/stat.h>
#include <unistd.h>

#include <vector>  // before boost/dll (GCC 12 needs it for library_info)
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include <boost/dll/shared_library.hpp>

#include "plugins/child_process.hpp"
#include "util/text.hpp"

// The executable's own ELF header (GNU ld, gold and lld define it): plugins must match its machine.
extern "C" const ElfW(Ehdr) __ehdr_start __attribute__((weak));

namespace gdsmc::host {

namespace fs = std::filesystem;

namespace {

// Reads exactly n bytes at offset (false on a short read or an error).
bool read_at(int fd, void* into, std::size_t n, off_t offset) {
  auto* p = static_cast<char*>(into);
  while (n > 0) {
    const ssize_t r = ::pread(fd, p, n, offset);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r;
    n -= static_cast<std::size_t>(r);
    offset += r;
  }
  return true;
}

// offset + length, saturated: the headers of a broken file may hold any numbers.
unsigned long long end_of(unsigned long long offset, unsigned long long length) {
  unsigned long long end;
  return __builtin_add_overflow(offset, length, &end) ? ~0ull : end;
}

const char* const kRemedy = "; rebuild the plugin or remove the file from the plugin path";

}  // namespace

std::string library_file_problem(const fs::path& file) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);  // follows symbolic links (the system limits their depth)
  if (ec.value() == ELOOP) return "is a symbolic link loop (too many levels of symbolic links); fix or remove the link";
  if (st.type() == fs::file_type::not_found) {
    if (fs::is_symlink(fs::symlink_status(file, ec)))
      return "is a symbolic link to " + fs::read_symlink(file, ec).string() + ", which does not exist; fix or remove the link";
    return "does not exist";
  }
  if (ec) return "cannot be examined (" + ec.message() + ")";
  if (st.type() == fs::file_type::directory)
    return "is a directory, not a shared library (a plugin is a .so file built with gdsmc_add_plugin)";
  if (st.type() != fs::file_type::regular)
    return "is not a regular file (a FIFO, socket or device), not a shared library";
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::string("cannot be read (") + std::strerror(errno) + ")";
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat info {};
  if (::fstat(fd, &info) != 0) return std::string("cannot be examined (") + std::strerror(errno) + ")";
  const auto size = static_cast<unsigned long long>(info.st_size);
  if (size == 0) return std::string("is empty (0 bytes), not a shared library") + kRemedy;
  ElfW(Ehdr) eh{};
  if (size < sizeof eh || !read_at(fd, &eh, sizeof eh, 0)) {
    if (size >= SELFMAG && read_at(fd, &eh, SELFMAG, 0) && std::memcmp(eh.e_ident, ELFMAG, SELFMAG) == 0)
      return fmt("is truncated (%llu bytes, shorter than an ELF header)", size) + kRemedy;
    return fmt("is not a shared library (%llu bytes, no ELF header)", size) + kRemedy;
  }
  if (std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0)
    return std::string("is not a shared library (it does not start with an ELF header)") + kRemedy;
  const ElfW(Ehdr)* self = &__ehdr_start;
  if (self && (eh.e_ident[EI_CLASS] != self->e_ident[EI_CLASS] || eh.e_ident[EI_DATA] != self->e_ident[EI_DATA] ||
               eh.e_machine != self->e_machine))
    return fmt("is built for another machine (ELF class %d, byte order %d, machine %d; this gdsmc: %d, %d, %d); "
               "rebuild the plugin on this machine",
               eh.e_ident[EI_CLASS], eh.e_ident[EI_DATA], eh.e_machine, self->e_ident[EI_CLASS],
               self->e_ident[EI_DATA], self->e_machine);
  if (eh.e_type != ET_DYN)
    return "is an ELF file but not a shared library (an executable or an object file); a plugin is a MODULE library "
           "built with gdsmc_add_plugin";
  if (eh.e_phentsize != sizeof(ElfW(Phdr)) || eh.e_phnum == 0 || (eh.e_shnum && eh.e_shentsize != sizeof(ElfW(Shdr))))
    return std::string("is a malformed shared library (its ELF header is inconsistent)") + kRemedy;
  // A truncated copy maps pages past its end, and touching them is SIGBUS: every table and every
  // loaded segment must lie inside the file.
  unsigned long long needed = end_of(eh.e_phoff, eh.e_phnum * sizeof(ElfW(Phdr)));
  if (eh.e_shnum) needed = std::max(needed, end_of(eh.e_shoff, eh.e_shnum * sizeof(ElfW(Shdr))));
  if (needed <= size) {
    std::vector<ElfW(Phdr)> ph(eh.e_phnum);
    if (!read_at(fd, ph.data(), ph.size() * sizeof(ElfW(Phdr)), static_cast<off_t>(eh.e_phoff)))
      return std::string("cannot be read in full (") + std::strerror(errno) + ")";
    for (const auto& h : ph)
      if (h.p_type == PT_LOAD || h.p_type == PT_DYNAMIC)
        needed = std::max(needed, end_of(h.p_offset, h.p_filesz));
  }
  if (needed > size)
    return fmt("is truncated (%llu bytes, but its ELF headers describe %llu: an interrupted copy or build?)", size,
               needed) + kRemedy;
  return "";
}

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
    c.remedy = entry.abi_major < sdk_abi_major
                   ? "rebuild the plugin against this gdsmc's SDK; one written for an SDK before " +
                         std::to_string(sdk_abi_major) + ".0 needs porting first (plugin author guide, section "
                         "'Porting to SDK 6.0': a collision rule no longer carries the candidate loop, the host does)"
                   : "rebuild the plugin against this gdsmc's SDK";
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

namespace {

// load_plugin without its safety checks: what the probe runs in its child process.
LoadedPlugin load_unchecked(const fs::path& file) {
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
  try {
    p.content_hash = file_content_hash(file);
  } catch (const std::exception& e) {
    throw PluginLoadError(file.string() + ": " + e.what());
  }
  p.library = std::move(lib);
  return p;
}

// Longer than any sane initialisation, even on a loaded machine; a hanging library costs this once.
constexpr double kProbeSeconds = 10;

PluginInfo info_of(const LoadedPlugin& p) {
  const PluginDescriptor& d = *p.descriptor;
  return {p.file, d.name, d.kind, d.version, d.summary, p.abi_major, p.abi_minor};
}

// What the probe sends for one library: 'E' and the error, or 'P' and the PluginInfo fields
// separated by '\0' (no field holds one).
std::string encode_error(const std::string& error) { return "E" + error; }
std::string encode(const LoadedPlugin& p) {
  const PluginInfo i = info_of(p);
  const char z = '\0';
  return "P" + i.name + z + std::to_string(static_cast<int>(i.kind)) + z + i.version + z + i.summary + z +
         std::to_string(i.abi_major) + z + std::to_string(i.abi_minor);
}

Examined decode(const fs::path& file, const std::string& m) {
  Examined e;
  e.info.file = file;
  if (m.empty() || m[0] != 'P') {
    e.error = m.size() > 1 ? m.substr(1) : file.string() + ": cannot be loaded (no reason was given)";
    return e;
  }
  std::vector<std::string> f(1);
  for (std::size_t k = 1; k < m.size(); ++k)
    if (m[k] == '\0') f.emplace_back();
    else f.back() += m[k];
  try {
    if (f.size() != 6) throw std::invalid_argument("fields");
    e.info.name = f[0];
    e.info.kind = static_cast<PluginKind>(std::stoi(f[1]));
    e.info.version = f[2];
    e.info.summary = f[3];
    e.info.abi_major = static_cast<std::uint32_t>(std::stoul(f[4]));
    e.info.abi_minor = static_cast<std::uint32_t>(std::stoul(f[5]));
  } catch (const std::exception&) {
    e.error = file.string() + ": its probe sent an unreadable report" + kRemedy;
  }
  return e;
}

// Loads the file here and reports on it as the probe would (when no child can be started).
Examined examine_here(const fs::path& file) {
  Examined e;
  e.info.file = file;
  try {
    e.info = info_of(load_unchecked(file));
  } catch (const PluginLoadError& err) {
    e.error = err.what();
  }
  return e;
}

// The probe of the files that passed library_file_problem.
std::vector<Examined> probe(const std::vector<fs::path>& files) {
  std::vector<Examined> out(files.size());
  std::size_t next = 0;
  while (next < files.size()) {
    // One child loads the libraries one after the other (one fork for a whole directory), and
    // reports on each before the next; a new child goes on after one that died.
    const std::size_t first = next;
    const ChildOutcome c = run_in_child(
        [&](ChildReport& report) {
          std::vector<LoadedPlugin> keep;  // unloading would run the libraries' destructors for nothing
          for (std::size_t k = first; k < files.size(); ++k) {
            try {
              keep.push_back(load_unchecked(files[k]));
              report.send(encode(keep.back()));
            } catch (const std::exception& e) {
              report.send(encode_error(e.what()));
            } catch (...) {
              report.send(encode_error(files[k].string() + ": loading it threw an exception that is not a std::exception"));
            }
          }
        },
        kProbeSeconds, true);
    if (!c.failure.empty()) {  // no child (out of processes or memory): load them here, as before probing
      for (std::size_t k = first; k < files.size(); ++k) out[k] = examine_here(files[k]);
      break;
    }
    for (std::size_t k = 0; k < c.messages.size() && first + k < files.size(); ++k)
      out[first + k] = decode(files[first + k], c.messages[k]);
    next = first + c.messages.size();
    if (c.finished || next >= files.size()) break;
    // The child died loading files[next]. Blame it only if it was the first library that child
    // loaded (another library's initialisation may have broken the process), else retry it alone;
    // a hang is blamed at once (a retry would cost the time limit again).
    if (next > first && !c.timed_out) continue;
    const std::string f = files[next].string();
    out[next].info.file = files[next];
    if (c.timed_out)
      out[next].error = f + fmt(": did not finish loading within %g s (its initialisation hangs)", kProbeSeconds) + kRemedy;
    else if (c.signal)
      out[next].error = f + fmt(": crashed while being loaded (signal %d, %s: its initialisation or its plugin entry "
                                "point is broken)", c.signal, strsignal(c.signal)) + kRemedy;
    else
      out[next].error = f + fmt(": ended the process while being loaded (exit status %d)", c.exit_status) + kRemedy;
    ++next;
  }
  return out;
}

}  // namespace

std::vector<Examined> examine_libraries(const std::vector<fs::path>& files) {
  std::vector<Examined> out(files.size());
  std::vector<fs::path> to_probe;
  std::vector<std::size_t> index;
  for (std::size_t k = 0; k < files.size(); ++k) {
    out[k].info.file = files[k];
    if (const std::string problem = library_file_problem(files[k]); !problem.empty()) {
      out[k].error = files[k].string() + ": " + problem;
    } else {
      to_probe.push_back(files[k]);
      index.push_back(k);
    }
  }
  std::vector<Examined> probed = probe(to_probe);
  for (std::size_t j = 0; j < probed.size(); ++j) out[index[j]] = std::move(probed[j]);
  return out;
}

LoadedPlugin load_examined(const PluginInfo& info) {
  LoadedPlugin p = load_unchecked(info.file);
  if (p.descriptor->name != info.name || p.descriptor->kind != info.kind)
    throw PluginLoadError(info.file.string() + ": changed while gdsmc was running (it was plugin '" + info.name +
                          "', now it is '" + p.descriptor->name + "'); run gdsmc again");
  return p;
}

LoadedPlugin load_plugin(const fs::path& file) {
  const Examined e = examine_libraries({file}).front();
  if (!e.error.empty()) throw PluginLoadError(e.error);
  return load_examined(e.info);
}

std::shared_ptr<PluginObject> create_object(const LoadedPlugin& plugin, const Params& params) {
  PluginObject* raw = plugin.descriptor->create(params);
  if (!raw) throw std::runtime_error("plugin '" + plugin.descriptor->name + "' factory returned nothing");
  auto library = plugin.library;
  // The deleter holds the library: it is unloaded (if ever) only after the object is gone.
  return std::shared_ptr<PluginObject>(raw, [library](PluginObject* o) { delete o; });
}

}  // namespace gdsmc::host
