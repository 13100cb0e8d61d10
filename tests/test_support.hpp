// Helpers shared by the gdsmc tests: temporary directories, pipelines written from strings, the
// gdsmc executable run as a subprocess, HDF5 files read back with the C API, and the in-process
// host (load a pipeline, run an engine).
#pragma once
#include <fcntl.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "config/pipeline.hpp"
#include "engine/engine.hpp"
#include "plugins/loader.hpp"
#include "plugins/registry.hpp"

extern char** environ;

namespace gdsmc::test {

namespace fs = std::filesystem;

// Seconds of the steady clock since `t`.
inline double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The in-tree plugins (<build>/plugins) and the test-only ones (<build>/test-plugins).
inline fs::path plugin_dir() { return GDSMC_TEST_PLUGIN_DIR; }
inline fs::path test_plugin_dir() { return fs::path(GDSMC_BINARY_DIR) / "test-plugins"; }
inline fs::path test_plugin(const std::string& name) { return test_plugin_dir() / ("gdsmc_" + name + ".so"); }
inline fs::path executable() { return GDSMC_EXECUTABLE; }
inline fs::path source_dir() { return GDSMC_SOURCE_DIR; }

// A fresh directory under $TMPDIR (or /tmp), removed with everything in it on destruction.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string tmpl = std::string(base && *base ? base : "/tmp") + "/gdsmc-test-XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data())) throw std::runtime_error("mkdtemp failed: " + std::string(std::strerror(errno)));
    path_ = buf.data();
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

  // Write `text` to <dir>/<name> and return the path.
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    std::ofstream out(p, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + p.string());
    return p;
  }
  // Names of the regular files in the directory (not recursive), sorted.
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_))
      if (e.is_regular_file()) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  // Every entry (file or directory, recursively) other than those named in `except`.
  std::vector<std::string> entries_except(const std::vector<std::string>& except) const {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(path_)) {
      const std::string rel = fs::relative(e.path(), path_).string();
      if (std::find(except.begin(), except.end(), rel) == except.end()) names.push_back(rel);
    }
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
  std::string s;
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? sep : "") + v[k];
  return s;
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// `text` with the first `from` replaced by `to` (a test bug if `from` is not there).
inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("test bug: '" + from + "' not in the text");
  return text.replace(at, from.size(), to);
}

// The lines of `text` that start with `prefix`.
inline std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

// A homogeneous cooling state small enough for a test to run in a fraction of a second.
inline const std::string kSmallHcsPipeline = R"(run:
  seed: 3
  particles: 400
  time_step: {value: 0.02, unit: tau0}
  stop: {collisions_per_particle: 1}
system: {density: 1.0e-3}
initial_state: maxwellian
collision: {plugin: inelastic_hard_spheres, alpha: 0.9}
diagnostics: [temperature]
output: {file: out.h5}
)";

// 1-based number of the first line of `text` that contains `needle` (0 if none).
inline int line_of(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  return 0;
}

// ---------------------------------------------------------------------------------------------
// The executable as a subprocess.

struct ProcessResult {
  int exit_code = -1;   // exit status, or -1 if killed by a signal
  int signal = 0;       // the signal that ended it, if any
  bool timed_out = false;
  std::string out, err;
  std::string describe() const {
    std::ostringstream s;
    s << "exit " << exit_code << (signal ? " (signal " + std::to_string(signal) + ")" : "")
      << (timed_out ? " (timed out)" : "") << "\n--- stdout ---\n" << out << "\n--- stderr ---\n" << err;
    return s.str();
  }
};

// A running gdsmc process: started in `cwd` with GDSMC_PLUGIN_PATH removed from the environment
// (the host then finds the build's plugins beside the executable); stdout and stderr go to files
// in a private directory (not `cwd`, so that tests can check what the run left in `cwd`).
// Limits set in the child before exec.
struct ProcessLimits {
  rlim_t address_space = RLIM_INFINITY;  // RLIMIT_AS, bytes
  bool core_dumps = true;                // false: RLIMIT_CORE 0
};
class Process {
 public:
  // `program` instead of gdsmc: a launcher (mpirun) whose arguments name gdsmc.
  Process(const std::vector<std::string>& args, const fs::path& cwd, const ProcessLimits& limits = {},
          const fs::path& program = executable()) {
    out_ = capture_.path() / "stdout";
    err_ = capture_.path() / "stderr";
    std::vector<std::string> argv_s;
    argv_s.push_back(program.string());
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<std::string> env_s;
    for (char** e = environ; *e; ++e)
      if (std::strncmp(*e, "GDSMC_PLUGIN_PATH=", 18) != 0) env_s.emplace_back(*e);
    // Everything the child needs is prepared before fork (no allocation after it).
    std::vector<char*> argv, envp;
    for (auto& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    for (auto& s : env_s) envp.push_back(s.data());
    envp.push_back(nullptr);
    const std::string cwd_s = cwd.string(), out_s = out_.string(), err_s = err_.string();
    const rlimit memory{limits.address_space, limits.address_space}, no_core{0, 0};
    pid_ = ::fork();  // only async-signal-safe calls in the child: other threads may fork too
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      const int o = ::open(out_s.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err_s.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int in = ::open("/dev/null", O_RDONLY);
      if (o < 0 || e < 0 || in < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0 || ::dup2(in, 0) < 0 ||
          ::chdir(cwd_s.c_str()) != 0 ||
          (limits.address_space != RLIM_INFINITY && ::setrlimit(RLIMIT_AS, &memory) != 0) ||
          (!limits.core_dumps && ::setrlimit(RLIMIT_CORE, &no_core) != 0))
        ::_exit(127);
      ::execve(argv[0], argv.data(), envp.data());
      ::_exit(127);
    }
  }
  Process(const Process&) = delete;
  ~Process() {
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      int status;
      ::waitpid(pid_, &status, 0);
    }
  }
  void send(int sig) { ::kill(pid_, sig); }
  pid_t pid() const { return pid_; }
  // Whether the process has installed a handler for `sig` (Linux: SigCgt in /proc/<pid>/status).
  bool catches(int sig) const {
    std::ifstream status("/proc/" + std::to_string(pid_) + "/status");
    std::string line;
    while (std::getline(status, line))
      if (line.rfind("SigCgt:", 0) == 0) {
        const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
        return (mask >> (sig - 1)) & 1ull;
      }
    return false;
  }
  // Wait until the process catches `sig` (true), or until it exits or `timeout_s` passes (false).
  bool wait_until_catches(int sig, double timeout_s = 30) {
    const auto start = std::chrono::steady_clock::now();
    while (seconds_since(start) < timeout_s) {
      if (catches(sig)) return true;
      siginfo_t info{};
      if (::waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid_)
        return false;  // it ended (left for wait() to reap)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  // Whether the process has ended (never blocks; wait() then returns at once).
  bool ended() {
    if (!reaped_ && ::waitpid(pid_, &status_, WNOHANG) == pid_) reaped_ = true;
    return reaped_;
  }
  // Wait up to `timeout_s` seconds (then SIGKILL it and report a timeout).
  ProcessResult wait(double timeout_s = 120) {
    ProcessResult r;
    const auto start = std::chrono::steady_clock::now();
    while (!ended()) {
      if (seconds_since(start) > timeout_s) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status_, 0);
        reaped_ = true;
        r.timed_out = true;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (WIFEXITED(status_)) r.exit_code = WEXITSTATUS(status_);
    if (WIFSIGNALED(status_)) r.signal = WTERMSIG(status_);
    r.out = read_text(out_);
    r.err = read_text(err_);
    return r;
  }
  // The stderr written so far.
  std::string err_so_far() const { return read_text(err_); }

 private:
  TempDir capture_;
  fs::path out_, err_;
  pid_t pid_ = -1;
  int status_ = 0;
  bool reaped_ = false;
};

// A shell command line (sh -c), with GDSMC_PLUGIN_PATH cleared; stdout and stderr together.
struct ShellResult {
  int status = -1;  // exit status, or -1 if it did not exit normally
  std::string out;
};
inline ShellResult shell(const std::string& command) {
  ShellResult r;
  FILE* p = ::popen(("GDSMC_PLUGIN_PATH= " + command + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

inline ProcessResult run_gdsmc(const std::vector<std::string>& args, const fs::path& cwd, double timeout_s = 120) {
  Process p(args, cwd);
  return p.wait(timeout_s);
}

// A small valid pipeline (a homogeneous cooling state of 1000 particles to s = 5); the tests change
// it with --set or the arguments.
inline std::string small_pipeline(const std::string& run_extra = "", const std::string& stop = "{collisions_per_particle: 5}",
                                  int particles = 1000, double alpha = 0.9, const std::string& diagnostics = "  - {plugin: temperature}\n") {
  return "run:\n"
         "  seed: 3\n"
         "  particles: " + std::to_string(particles) + "\n"
         "  time_step: {value: 0.01, unit: tau0, follow_temperature: true}\n"
         "  stop: " + stop + "\n" + run_extra +
         "system:\n"
         "  density: 1.0e-3\n"
         "  temperature: 1.0\n"
         "initial_state: {plugin: maxwellian}\n"
         "collision: {plugin: inelastic_hard_spheres, alpha: " + std::to_string(alpha) + "}\n"
         "diagnostics:\n" + diagnostics +
         "output: {file: out.h5}\n";
}

// `gdsmc <command> pipeline.yaml [args]` in a fresh directory; what it printed and what it left there.
struct Outcome {
  ProcessResult result;
  std::vector<std::string> left;  // entries other than the pipeline
};
inline Outcome gdsmc_in_dir(const std::string& command, const std::string& yaml, const std::vector<std::string>& args,
                            double timeout_s = 30) {
  TempDir dir;
  const auto file = dir.write("pipeline.yaml", yaml);
  std::vector<std::string> argv = {command, file.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  Outcome o;
  o.result = run_gdsmc(argv, dir.path(), timeout_s);
  o.left = dir.entries_except({"pipeline.yaml"});
  return o;
}

// ---------------------------------------------------------------------------------------------
// HDF5 read-back (C API).

namespace h5 {

struct Handle {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  Handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  Handle(const Handle&) = delete;
  ~Handle() {
    if (id >= 0) close(id);
  }
  explicit operator bool() const { return id >= 0; }
  operator hid_t() const { return id; }
};

class File {
 public:
  explicit File(const fs::path& p) : h_(open(p), H5Fclose) {
    if (!h_) throw std::runtime_error("cannot open HDF5 file " + p.string());
  }
  hid_t id() const { return h_.id; }

 private:
  static hid_t open(const fs::path& p) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  }
  Handle h_;
};

inline bool exists(hid_t loc, const std::string& path) {
  // Check every prefix: H5Lexists fails on a path whose intermediate group is missing.
  std::size_t pos = 0;
  while (true) {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (!prefix.empty() && prefix != "/" && H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

inline bool is_dataset(hid_t loc, const std::string& path) {
  if (!exists(loc, path)) return false;
  H5O_info_t info;
  if (H5Oget_info_by_name(loc, path.c_str(), &info, H5P_DEFAULT) < 0) return false;
  return info.type == H5O_TYPE_DATASET;
}

inline std::vector<hsize_t> shape(hid_t loc, const std::string& path) {
  Handle d(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d) throw std::runtime_error("no dataset " + path);
  Handle s(H5Dget_space(d), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(s);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank > 0) H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  return dims;
}

// A numeric dataset converted to double (rank 0 gives one value).
inline std::vector<double> read_doubles(hid_t loc, const std::string& path) {
  Handle d(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d) throw std::runtime_error("no dataset " + path);
  Handle s(H5Dget_space(d), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(n, 0)));
  if (!v.empty() && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    throw std::runtime_error("cannot read " + path + " as double");
  return v;
}

inline double read_scalar(hid_t loc, const std::string& path) {
  const auto v = read_doubles(loc, path);
  if (v.size() != 1) throw std::runtime_error(path + " is not a scalar");
  return v[0];
}

// A string dataset (fixed or variable length) as text.
inline std::vector<std::string> read_strings(hid_t loc, const std::string& path) {
  Handle d(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  Handle ftype(H5Dget_type(d), H5Tclose);
  Handle s(H5Dget_space(d), H5Sclose);
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(s));
  std::vector<std::string> out;
  if (H5Tis_variable_str(ftype) > 0) {
    Handle mtype(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mtype, H5T_VARIABLE);
    H5Tset_cset(mtype, H5Tget_cset(ftype));  // HDF5 does not convert between ASCII and UTF-8
    std::vector<char*> p(n, nullptr);
    if (n && H5Dread(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()) < 0)
      throw std::runtime_error("cannot read strings " + path);
    for (char* c : p) out.emplace_back(c ? c : "");
    if (n) H5Dvlen_reclaim(mtype, s, H5P_DEFAULT, p.data());
  } else {
    const std::size_t len = H5Tget_size(ftype);
    std::vector<char> buf(n * len);
    if (n && H5Dread(d, ftype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0)
      throw std::runtime_error("cannot read strings " + path);
    for (std::size_t k = 0; k < n; ++k) out.emplace_back(std::string(buf.data() + k * len, len).c_str());
  }
  return out;
}

// The raw content of a dataset, for bit-for-bit comparison: numbers as their bytes in the
// native layout of their own type, strings as text.
inline std::string content_bytes(hid_t loc, const std::string& path) {
  Handle d(H5Dopen2(loc, path.c_str(), H5P_DEFAULT), H5Dclose);
  Handle ftype(H5Dget_type(d), H5Tclose);
  if (H5Tget_class(ftype) == H5T_STRING) return join(read_strings(loc, path), std::string(1, '\0'));
  Handle mtype(H5Tget_native_type(ftype, H5T_DIR_ASCEND), H5Tclose);
  Handle s(H5Dget_space(d), H5Sclose);
  const auto n = static_cast<std::size_t>(H5Sget_simple_extent_npoints(s));
  std::string bytes(n * H5Tget_size(mtype), '\0');
  if (n && H5Dread(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()) < 0)
    throw std::runtime_error("cannot read " + path);
  return bytes;
}

inline bool has_attribute(hid_t loc, const std::string& object, const std::string& name) {
  return H5Aexists_by_name(loc, object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

inline std::string read_string_attribute(hid_t loc, const std::string& object, const std::string& name) {
  Handle a(H5Aopen_by_name(loc, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a) throw std::runtime_error("no attribute " + object + "@" + name);
  Handle ftype(H5Aget_type(a), H5Tclose);
  if (H5Tget_class(ftype) != H5T_STRING) throw std::runtime_error(object + "@" + name + " is not text");
  if (H5Tis_variable_str(ftype) > 0) {
    Handle mtype(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mtype, H5T_VARIABLE);
    H5Tset_cset(mtype, H5Tget_cset(ftype));
    char* p = nullptr;
    if (H5Aread(a, mtype, &p) < 0) throw std::runtime_error("cannot read " + object + "@" + name);
    std::string s = p ? p : "";
    Handle space(H5Aget_space(a), H5Sclose);
    H5Dvlen_reclaim(mtype, space, H5P_DEFAULT, &p);
    return s;
  }
  std::string buf(H5Tget_size(ftype), '\0');
  if (H5Aread(a, ftype, buf.data()) < 0) throw std::runtime_error("cannot read " + object + "@" + name);
  return std::string(buf.c_str());
}

inline double read_number_attribute(hid_t loc, const std::string& object, const std::string& name) {
  Handle a(H5Aopen_by_name(loc, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a) throw std::runtime_error("no attribute " + object + "@" + name);
  double v = 0;
  if (H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0) throw std::runtime_error("cannot read " + object + "@" + name + " as a number");
  return v;
}

// Every object of the file: "/a/b" -> type, in visit order.
inline std::map<std::string, H5O_type_t> objects(hid_t file) {
  std::map<std::string, H5O_type_t> out;
  auto cb = [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    auto* m = static_cast<std::map<std::string, H5O_type_t>*>(data);
    const std::string n = name;
    if (n != ".") (*m)["/" + n] = info->type;
    return 0;
  };
  if (H5Ovisit(file, H5_INDEX_NAME, H5_ITER_INC, cb, &out) < 0) throw std::runtime_error("H5Ovisit failed");
  return out;
}

inline std::vector<std::string> datasets(hid_t file) {
  std::vector<std::string> v;
  for (const auto& [name, type] : objects(file))
    if (type == H5O_TYPE_DATASET) v.push_back(name);
  return v;
}

// Names of the direct members of a group.
inline std::vector<std::string> members(hid_t loc, const std::string& group) {
  std::vector<std::string> out;
  Handle g(H5Gopen2(loc, group.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g) throw std::runtime_error("no group " + group);
  auto cb = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  H5Literate(g, H5_INDEX_NAME, H5_ITER_INC, nullptr, cb, &out);
  return out;
}

// The raw bytes of a dataset or attribute (variable-length strings as their characters).
inline std::string value_bytes(hid_t object, hid_t type, hid_t space, bool attribute) {
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (H5Tis_variable_str(type) > 0) {
    std::vector<char*> strings(static_cast<std::size_t>(n), nullptr);
    h5::Handle mem(H5Tcopy(type), H5Tclose);  // the file's own string type (its character set)
    const herr_t r = attribute ? H5Aread(object, mem, strings.data())
                               : H5Dread(object, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, strings.data());
    if (r < 0) throw std::runtime_error("cannot read a string value");
    std::string out;
    for (char* s : strings) out += std::string(s ? s : "") + '\0';
    H5Dvlen_reclaim(mem, space, H5P_DEFAULT, strings.data());
    return out;
  }
  std::string out(static_cast<std::size_t>(n) * H5Tget_size(type), '\0');
  const herr_t r = attribute ? H5Aread(object, type, out.data())
                             : H5Dread(object, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  if (r < 0) throw std::runtime_error("cannot read a value");
  return out;
}

// Every dataset (path -> bytes) and every attribute (path@name -> bytes) of a file, but the wall
// times, wall_seconds and stage_seconds.* (the only values that may differ between two runs of
// the same pipeline).
inline std::map<std::string, std::string> contents(const fs::path& file) {
  h5::File f(file);
  std::map<std::string, std::string> out;
  auto attributes = [&](hid_t object, const std::string& path) {
    H5O_info_t info;
    H5Oget_info(object, &info);
    for (hsize_t k = 0; k < info.num_attrs; ++k) {
      h5::Handle a(H5Aopen_by_idx(object, ".", H5_INDEX_NAME, H5_ITER_INC, k, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
      char name[256];
      H5Aget_name(a, sizeof name, name);
      if (std::string(name) == "wall_seconds" || std::string(name).rfind("stage_seconds.", 0) == 0) continue;
      h5::Handle type(H5Aget_type(a), H5Tclose), space(H5Aget_space(a), H5Sclose);
      out[path + "@" + name] = value_bytes(a, type, space, true);
    }
  };
  attributes(f.id(), "/");
  for (const auto& [path, kind] : h5::objects(f.id())) {
    h5::Handle o(H5Oopen(f.id(), path.c_str(), H5P_DEFAULT), H5Oclose);
    attributes(o, path);
    if (kind != H5O_TYPE_DATASET) continue;
    h5::Handle type(H5Dget_type(o), H5Tclose), space(H5Dget_space(o), H5Sclose);
    out[path] = value_bytes(o, type, space, false);
  }
  return out;
}

}  // namespace h5

// ---------------------------------------------------------------------------------------------
// The host in-process.

// Load a pipeline written from `yaml` into <dir>/<name>, with the in-tree plugins on the search
// path. An Engine keeps a reference to the pipeline: keep the pipeline alive while it runs.
inline host::Pipeline load_yaml(const TempDir& dir, const std::string& yaml, const std::vector<std::string>& overrides = {},
                                const std::string& name = "pipeline.yaml") {
  const fs::path file = dir.write(name, yaml);
  return host::load_pipeline(file, overrides, {plugin_dir()});
}

// What the diagnostic group `group`, its series `column` or its scalar `name` holds after a run
// (throws if missing).
inline const host::DiagnosticOutput& diagnostic(const host::Engine& e, const std::string& group) {
  for (const auto& d : e.diagnostics())
    if (d.group() == group) return d;
  throw std::runtime_error("no diagnostic group '" + group + "'");
}
inline const std::vector<double>& series(const host::Engine& e, const std::string& group, const std::string& column) {
  const auto& d = diagnostic(e, group);
  for (const auto& c : d.columns)
    if (c.name == column) return c.values;
  throw std::runtime_error("no series '" + column + "' in group '" + group + "'");
}
inline double scalar(const host::Engine& e, const std::string& group, const std::string& name) {
  const auto& d = diagnostic(e, group);
  for (const auto& s : d.scalars)
    if (s.name == name) return s.value;
  throw std::runtime_error("no scalar '" + name + "' in group '" + group + "'");
}

// Sum of doubles with Neumaier's compensation: the error is about one rounding of the result
// plus N eps^2 sum|x|, negligible next to the round-off the tests bound.
class ExactishSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    if (std::fabs(sum_) >= std::fabs(x)) c_ += (sum_ - t) + x;
    else c_ += (x - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + c_; }

 private:
  double sum_ = 0, c_ = 0;
};

// Mean and standard error of independent values.
struct MeanError {
  double mean = 0, standard_error = 0;
};
inline MeanError mean_error(const std::vector<double>& x) {
  MeanError r;
  const double n = static_cast<double>(x.size());
  for (double v : x) r.mean += v;
  r.mean /= n;
  double var = 0;
  for (double v : x) var += (v - r.mean) * (v - r.mean);
  var /= (n - 1);
  r.standard_error = std::sqrt(var / n);
  return r;
}

// a2 of the HCS in the first Sonine approximation, d = 3 (paper 001, Eq. 2.16).
inline double sonine_a2(double alpha) {
  constexpr double d = 3.0;
  return 16.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha * alpha) /
         (25.0 + 24.0 * d - alpha * (57.0 - 8.0 * d) - 2.0 * (1.0 - alpha) * alpha * alpha);
}
// zeta(T0) tau0 of the HCS (paper 001, Eqs. 2.14-2.15 with d = 3; paper 000, Eq. 2.16).
inline double haff_zeta_tau0(double alpha) {
  return 2.0 * (1.0 - alpha * alpha) * (1.0 + 3.0 * sonine_a2(alpha) / 16.0) / (3.0 * std::sqrt(M_PI));
}

}  // namespace gdsmc::test
