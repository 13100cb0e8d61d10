// `gdsmc conformance PLUGIN.so`: the plugin conformance runner (see conformance.hpp).
//
// Every check runs in a child process (fork), reports PASS / FAIL / SKIP with a message naming
// the plugin and the property, and a plugin that kills its process yields a CRASH line. Checks
// use the host's own paths: the loader, load_pipeline() on a generated pipeline (the same
// validation a user's pipeline gets) and the Engine, plus direct calls on plugin objects where a
// property needs controlled input (random pairs for a collision rule, permuted particles for a
// diagnostic, one step of dt against two of dt/2 for a forcing).
#include "conformance.hpp"

#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <vector>  // before boost/dll (GCC 12 needs it for library_info)
#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include <boost/dll/shared_library.hpp>
#include <yaml-cpp/yaml.h>

#include <gdsmc/collision.hpp>
#include <gdsmc/moments.hpp>

#include "engine.hpp"
#include "loader.hpp"
#include "output.hpp"
#include "particle_store.hpp"
#include "pipeline.hpp"

namespace gdsmc::host {

namespace {

namespace fs = std::filesystem;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Total momentum, kinetic energy (m = 1) and sum of speeds (the round-off scale) of all particles.
void velocity_totals(const ParticleSpan& p, Vec3& momentum, double& energy, double& speed_sum) {
  momentum = {};
  energy = speed_sum = 0;
  for (std::size_t i = 0; i < p.count; ++i) {
    const Vec3 v = p.velocity(i);
    momentum += v;
    energy += 0.5 * dot(v, v);
    speed_sum += norm(v);
  }
}

const char* kHelp = R"(gdsmc conformance PLUGIN.so [options]

Checks one plugin binary against the contract of its kind and prints one line per check:
  PASS | FAIL | SKIP | CRASH   check-name   message naming the plugin and the property
Every check runs in its own process: a plugin that crashes gives a CRASH line, not a dead
runner. Exit status: 0 when nothing failed or crashed, 1 otherwise, 2 for a bad command line.

Checks (by kind):
  all kinds    load, abi_version, descriptor, parameter_schema, defaults_construct,
               parameter_bounds (values at and inside the declared bounds construct or are
               refused with a message), out_of_range_rejected, wrong_type_rejected, determinism
  collision    collision.finite, collision.mass, collision.momentum, collision.energy,
               collision.rate (on random pairs and edge cases: zero relative velocity, grazing,
               huge and tiny speeds), collision.cell (collide_cell on a population)
  forcing      forcing.conservation (what conserves() declares), forcing.order (one step of dt
               against two of dt/2 scales as dt^(order+1))
  boundary     boundary.containment (no particle lost or left outside), boundary.wall_flux
  initial      initial.state (finite state, positive temperature)
  diagnostic   diagnostic.output (one value per series per record, units given),
               diagnostic.particle_order (values do not depend on the particle order)

Options:
  --params FILE.yaml   parameter values for the plugin (a mapping name: value, units as in a
                       pipeline); required parameters without a default get in-range values
  --context FILE.yaml  a pipeline whose initial_state and collision entries (and plugins: paths)
                       are used around the plugin, e.g. for a diagnostic that needs the
                       attributes of a particular collision rule (default: maxwellian and
                       inelastic_hard_spheres from the plugin search path)
  --seed N             seed of every random input (default 1); a failure names it
  --only CHECK         run only CHECK (a name, or a prefix such as 'collision'); repeatable,
                       comma-separated lists allowed
  --plugin-path P      more plugin directories or files (for the context's plugins)
  --list               list the checks that apply to the plugin and exit
  --no-fork            run the checks in this process (for a debugger)
  --timeout S          seconds allowed per check (default 120)
)";

// --------------------------------------------------------------------------------------------
// Results and isolation

enum class Status { pass, fail, skip, crash };

struct Result {
  Status status = Status::pass;
  std::string message;
};
Result pass(std::string m) { return {Status::pass, std::move(m)}; }
Result fail(std::string m) { return {Status::fail, std::move(m)}; }
Result skip(std::string m) { return {Status::skip, std::move(m)}; }

const char* status_text(Status s) {
  switch (s) {
    case Status::pass: return "PASS";
    case Status::fail: return "FAIL";
    case Status::skip: return "SKIP";
    case Status::crash: return "CRASH";
  }
  return "?";
}

std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* f, ...) {
  char buf[2048];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

std::string vec_text(const Vec3& v) { return fmt("(%.6g, %.6g, %.6g)", v.x, v.y, v.z); }

Result guarded(const std::function<Result()>& fn) {
  try {
    return fn();
  } catch (const PipelineError& e) {
    std::string m;
    for (const auto& s : e.messages()) m += (m.empty() ? "" : "; ") + s;
    return fail("the test pipeline was refused: " + m);
  } catch (const std::exception& e) {
    return fail(std::string("threw: ") + e.what());
  } catch (...) {
    return fail("threw an exception that is not a std::exception");
  }
}

// Runs fn in a child process; a signal or an exit without a result is a crash.
Result isolated(const std::function<Result()>& fn, bool use_fork, int timeout_seconds) {
  if (!use_fork) return guarded(fn);
  int fds[2];
  if (::pipe(fds) != 0) return fail(std::string("cannot create a pipe: ") + std::strerror(errno));
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return fail(std::string("cannot fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::close(fds[0]);
    ::alarm(static_cast<unsigned>(timeout_seconds));
    const Result r = guarded(fn);
    std::string out(1, static_cast<char>('0' + static_cast<int>(r.status)));
    out += r.message;
    std::size_t off = 0;
    while (off < out.size()) {
      const ssize_t w = ::write(fds[1], out.data() + off, out.size() - off);
      if (w <= 0) break;
      off += static_cast<std::size_t>(w);
    }
    ::close(fds[1]);
    std::cout.flush();
    std::fflush(nullptr);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string data;
  char buf[4096];
  for (;;) {
    const ssize_t r = ::read(fds[0], buf, sizeof buf);
    if (r > 0) data.append(buf, static_cast<std::size_t>(r));
    else if (r < 0 && errno == EINTR) continue;
    else break;
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (sig == SIGALRM) return fail(fmt("did not finish within %d s (--timeout)", timeout_seconds));
    return {Status::crash, fmt("crashed: the check's process died of signal %d (%s)", sig, strsignal(sig))};
  }
  if (data.empty())
    return {Status::crash, fmt("crashed: the check's process exited (status %d) without reporting", WEXITSTATUS(status))};
  Result r;
  r.status = static_cast<Status>(data[0] - '0');
  r.message = data.substr(1);
  return r;
}

// --------------------------------------------------------------------------------------------
// The plugin under test and how to build pipelines around it

using Assignment = std::map<std::string, std::string>;  // parameter -> YAML text of its value

struct Config {
  fs::path plugin;
  std::vector<fs::path> plugin_paths;
  std::optional<fs::path> params_file, context_file;
  std::uint64_t seed = 1;
  std::vector<std::string> only;
  bool fork = true, list = false;
  int timeout = 120;
};

struct Subject {
  Config cfg;
  fs::path file;
  fs::path workdir;
  std::optional<LoadedPlugin> loaded;
  Assignment user_params;
  std::string context_initial, context_collision;  // YAML flow text; empty: default fillers
  std::vector<std::string> context_forcings;        // YAML flow text of the context's forcings
  std::vector<fs::path> context_paths;

  const PluginDescriptor& desc() const { return *loaded->descriptor; }
  PluginKind kind() const { return desc().kind; }
};

std::string yaml_text(const YAML::Node& n) {
  YAML::Emitter e;
  e << YAML::Flow << n;
  return e.c_str();
}

std::string num(double v) { return fmt("%.17g", v); }

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// A value inside the declared range (for required parameters without a default).
std::string in_range_value(const ParamSpec& s) {
  switch (s.type) {
    case ParamType::real: {
      if (s.min && s.max) return num(0.5 * (*s.min + *s.max));
      if (s.min) return num(*s.min + std::max(1.0, std::fabs(*s.min)));
      if (s.max) return num(*s.max - std::max(1.0, std::fabs(*s.max)));
      return "1";
    }
    case ParamType::integer: {
      double v = 1;
      if (s.min && s.max) v = std::floor(0.5 * (*s.min + *s.max));
      else if (s.min) v = std::floor(*s.min) + 1;
      else if (s.max) v = std::ceil(*s.max) - 1;
      return fmt("%.0f", v);
    }
    case ParamType::boolean: return "false";
    case ParamType::choice: return s.choices.empty() ? "none" : quoted(s.choices.front());
    case ParamType::string: return quoted("conformance");
  }
  return "1";
}

Assignment base_assignment(const Subject& s) {
  Assignment a = s.user_params;
  for (const auto& spec : s.desc().parameters)
    if (!spec.default_ && !a.count(spec.name)) a[spec.name] = in_range_value(spec);
  return a;
}

std::string describe_assignment(const Subject& s, const Assignment& a) {
  std::string t;
  for (const auto& spec : s.desc().parameters) {
    std::string v;
    if (auto it = a.find(spec.name); it != a.end()) v = it->second;
    else if (spec.default_) v = value_text(*spec.default_) + " (default)";
    t += (t.empty() ? "" : ", ") + spec.name + " = " + v;
  }
  return t.empty() ? "no parameters" : t;
}

std::string slot_path(PluginKind k) {
  switch (k) {
    case PluginKind::collision_rule: return "collision";
    case PluginKind::initial_state: return "initial_state";
    case PluginKind::forcing: return "forcings[0]";
    case PluginKind::boundary: return "boundaries[0]";
    case PluginKind::diagnostic: return "diagnostics[0]";
  }
  return "?";
}

const PluginUse& slot(const Pipeline& p, PluginKind k) {
  switch (k) {
    case PluginKind::collision_rule: return p.collision;
    case PluginKind::initial_state: return p.initial_state;
    case PluginKind::forcing: return p.forcings.at(0);
    case PluginKind::boundary: return p.boundaries.at(0);
    case PluginKind::diagnostic: return p.diagnostics.at(0);
  }
  throw std::logic_error("bad kind");
}

// The plugin's own entries among a refused pipeline's messages.
std::vector<std::string> own_errors(const PipelineError& e, PluginKind k) {
  const std::string path = slot_path(k);
  std::vector<std::string> out;
  for (const auto& m : e.messages())
    if (m.find(": " + path + ":") != std::string::npos || m.find(": " + path + ".") != std::string::npos ||
        m.find(": " + path + "[") != std::string::npos)
      out.push_back(m);
  return out;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& m : v) s += (s.empty() ? "" : "; ") + m;
  return s;
}

// Fillers for the slots the plugin does not occupy: the --context pipeline's entries, else the
// preferred in-tree plugin, else the first plugin of the kind whose parameters all have defaults.
std::string filler(const Subject& s, PluginKind kind) {
  static std::map<PluginKind, std::string> cache;
  if (auto it = cache.find(kind); it != cache.end()) return it->second;
  const std::string& from_context = kind == PluginKind::initial_state ? s.context_initial : s.context_collision;
  if (!from_context.empty()) return cache[kind] = from_context;
  PluginRegistry reg;
  auto add = [&](const fs::path& p) {
    try {
      reg.add(p);
    } catch (const std::exception&) {
    }
  };
  add(s.file);
  for (const auto& p : s.cfg.plugin_paths) add(p);
  for (const auto& p : s.context_paths) add(p);
  for (const auto& p : PluginRegistry::default_search_path()) add(p);
  const char* preferred = kind == PluginKind::initial_state ? "maxwellian" : "inelastic_hard_spheres";
  if (const LoadedPlugin* lp = reg.find(preferred); lp && lp->descriptor->kind == kind) {
    // An inelastic gas, so that rules, forcings and diagnostics see dissipation.
    const bool has_alpha = std::any_of(lp->descriptor->parameters.begin(), lp->descriptor->parameters.end(),
                                       [](const ParamSpec& p) { return p.name == "alpha"; });
    return cache[kind] = kind == PluginKind::collision_rule && has_alpha
                             ? std::string("{plugin: inelastic_hard_spheres, alpha: 0.8}")
                             : std::string(preferred);
  }
  for (const auto& lp : reg.plugins()) {
    if (lp.descriptor->kind != kind) continue;
    bool all_defaults = true;
    for (const auto& p : lp.descriptor->parameters) all_defaults = all_defaults && p.default_.has_value();
    if (all_defaults) return cache[kind] = lp.descriptor->name;
  }
  throw std::runtime_error(std::string("cannot build a test pipeline: no ") + to_string(kind) +
                           " plugin on the plugin search path to go with this one (give --plugin-path, "
                           "GDSMC_PLUGIN_PATH or --context)");
}

std::string entry_text(const std::string& plugin, const Assignment& a) {
  std::string t = "{plugin: " + quoted(plugin);
  for (const auto& [k, v] : a) t += ", " + k + ": " + v;
  return t + "}";
}

constexpr double kTimeStepTau0 = 0.05;
constexpr double kDensity = 1.0e-3;

// Write and load a pipeline with the plugin (parameters `a`) in its slot.
std::unique_ptr<Pipeline> load_test_pipeline(const Subject& s, const Assignment& a, std::size_t particles = 256) {
  static int counter = 0;
  const PluginKind k = s.kind();
  const std::string self = entry_text(s.desc().name, a);
  std::ostringstream y;
  y << "run: {seed: " << s.cfg.seed << ", particles: " << particles << ", time_step: {value: " << kTimeStepTau0
    << ", unit: tau0}, stop: {collisions_per_particle: 1}}\n";
  y << "system: {density: " << num(kDensity) << ", temperature: 1.0}\n";
  y << "initial_state: " << (k == PluginKind::initial_state ? self : filler(s, PluginKind::initial_state)) << "\n";
  y << "collision: " << (k == PluginKind::collision_rule ? self : filler(s, PluginKind::collision_rule)) << "\n";
  if (k == PluginKind::forcing || !s.context_forcings.empty()) {
    y << "forcings: [";
    if (k == PluginKind::forcing) y << self;
    for (std::size_t i = 0; i < s.context_forcings.size(); ++i)
      y << (i || k == PluginKind::forcing ? ", " : "") << s.context_forcings[i];
    y << "]\n";
  }
  if (k == PluginKind::boundary) y << "boundaries: [" << self << "]\n";
  if (k == PluginKind::diagnostic) y << "diagnostics: [" << self << "]\n";
  if (!s.context_paths.empty()) {
    y << "plugins: [";
    for (std::size_t i = 0; i < s.context_paths.size(); ++i) y << (i ? ", " : "") << quoted(s.context_paths[i].string());
    y << "]\n";
  }
  y << "output: {file: " << quoted((s.workdir / "unused.h5").string()) << "}\n";
  const fs::path file = s.workdir / fmt("pipeline-%d-%d.yaml", static_cast<int>(::getpid()), counter++);
  {
    std::ofstream out(file);
    out << y.str();
  }
  std::vector<fs::path> extra{s.file};
  for (const auto& p : s.cfg.plugin_paths) extra.push_back(p);
  return std::make_unique<Pipeline>(load_pipeline(file, {}, extra));
}

// --------------------------------------------------------------------------------------------
// A small engine-like harness for direct calls on plugin objects

struct Snapshot {
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<std::vector<double>> attributes;
};

struct Harness {
  std::unique_ptr<Pipeline> pipeline;
  const PluginUse* use = nullptr;
  std::shared_ptr<PluginObject> initial, collision, subject;
  std::vector<AttributeSpec> attributes;
  SystemInfo sys;
  QuantityBoard board;
  CellMoments global;
  StepContext ctx;
  ParticleStore store;
  double remainder = 0;

  ParticleSpan span() { return store.span(); }
  void update_moments() {
    const VelocityMoments m = velocity_moments(store.span());
    global.count = m.count;
    global.number_density = sys.number_density;
    for (int a = 0; a < 3; ++a) global.mean_velocity[a] = m.mean[a];
    global.temperature = m.temperature;
  }
  std::shared_ptr<PluginObject> fresh_subject() const { return create_object(*use->plugin, use->params); }

  Snapshot save() {
    const ParticleSpan p = span();
    Snapshot s;
    auto copy = [&](const double* d) { return std::vector<double>(d, d + p.count); };
    s.x = copy(p.x); s.y = copy(p.y); s.z = copy(p.z);
    s.vx = copy(p.vx); s.vy = copy(p.vy); s.vz = copy(p.vz);
    for (std::size_t a = 0; a < p.attribute_count; ++a)
      s.attributes.emplace_back(p.attribute_data[a], p.attribute_data[a] + p.count * p.attribute_specs[a].components);
    return s;
  }
  // Restore a snapshot; with `perm`, particle k of the span is particle perm[k] of the snapshot.
  void restore(const Snapshot& s, const std::vector<std::uint32_t>* perm = nullptr) {
    const ParticleSpan p = span();
    for (std::size_t k = 0; k < p.count; ++k) {
      const std::size_t i = perm ? (*perm)[k] : k;
      p.x[k] = s.x[i]; p.y[k] = s.y[i]; p.z[k] = s.z[i];
      p.vx[k] = s.vx[i]; p.vy[k] = s.vy[i]; p.vz[k] = s.vz[i];
      for (std::size_t a = 0; a < p.attribute_count; ++a) {
        const std::size_t comps = static_cast<std::size_t>(p.attribute_specs[a].components);
        for (std::size_t c = 0; c < comps; ++c) p.attribute_data[a][c * p.count + k] = s.attributes[a][c * p.count + i];
      }
    }
    update_moments();
  }
  // Attributes that the initial state left at zero get random values (so that rules and
  // diagnostics that use them see something to work on).
  void randomize_zero_attributes(Rng& rng) {
    const ParticleSpan p = span();
    for (std::size_t a = 0; a < p.attribute_count; ++a) {
      const std::size_t n = p.count * static_cast<std::size_t>(p.attribute_specs[a].components);
      double* d = p.attribute_data[a];
      if (std::all_of(d, d + n, [](double v) { return v == 0.0; }))
        for (std::size_t k = 0; k < n; ++k) d[k] = rng.normal();
    }
  }
  // One collision stage of the filler (or tested) collision rule over the whole population.
  CellCollision collide(double dt, Rng& rng) {
    auto* rule = static_cast<CollisionRule*>(collision.get());
    CellCollision cell;
    cell.particles = span();
    cell.count = static_cast<std::uint32_t>(cell.particles.count);
    cell.volume = sys.volume;
    cell.sigma = sys.sigma;
    cell.dt = dt;
    cell.majorant = 6.0 * M_SQRT2 * std::sqrt(global.temperature);
    cell.remainder = remainder;
    cell.rng = &rng;
    rule->collide_cell(cell);
    remainder = cell.remainder;
    ctx.collisions += static_cast<double>(cell.accepted);
    ctx.candidates += static_cast<double>(cell.candidates);
    ctx.collision_energy_change += cell.energy_change;
    update_moments();
    return cell;
  }
};

std::unique_ptr<Harness> make_harness(const Subject& s, const Assignment& a, std::size_t n) {
  auto h = std::make_unique<Harness>();
  h->pipeline = load_test_pipeline(s, a, n);
  const Pipeline& p = *h->pipeline;
  h->use = &slot(p, s.kind());
  h->initial = create_object(*p.initial_state.plugin, p.initial_state.params);
  h->collision = create_object(*p.collision.plugin, p.collision.params);
  if (s.kind() == PluginKind::initial_state) h->subject = h->initial;
  else if (s.kind() == PluginKind::collision_rule) h->subject = h->collision;
  else h->subject = h->fresh_subject();
  std::vector<std::shared_ptr<PluginObject>> objects{h->initial, h->collision};
  if (h->subject != h->initial && h->subject != h->collision) objects.push_back(h->subject);
  for (const auto& f : p.forcings)  // the context's forcings (they may publish quantities)
    if (&f != h->use) objects.push_back(create_object(*f.plugin, f.params));
  for (const auto& o : objects)
    for (auto& at : o->attributes()) h->attributes.push_back(std::move(at));
  h->store.allocate(n, h->attributes);
  for (const auto& o : objects) o->publish(h->board);

  h->sys = p.system_info(n, 0);
  h->sys.seed = s.cfg.seed;
  const SystemInfo& sys = h->sys;

  StepContext& ctx = h->ctx;
  ctx.system = &h->sys;
  ctx.quantities = &h->board;
  ctx.key = stream_key(s.cfg.seed, 0);
  ctx.cells = &h->global;
  ctx.cell_count = 1;
  ctx.global = &h->global;
  ctx.dt = kTimeStepTau0 * sys.time_unit0;

  Rng rng(ctx.key, StreamPurpose::initial_state, 0, 0);
  static_cast<InitialState*>(h->initial.get())->generate(h->sys, h->span(), rng);
  h->update_moments();
  return h;
}

bool all_finite(const double* d, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(d[k])) return false;
  return true;
}

// First non-finite entry of the particle state, or "" when everything is finite.
std::string nonfinite_in(const ParticleSpan& p, bool positions = true) {
  const std::pair<const char*, const double*> arrays[] = {{"x", p.x}, {"y", p.y}, {"z", p.z},
                                                           {"vx", p.vx}, {"vy", p.vy}, {"vz", p.vz}};
  for (const auto& [name, d] : arrays) {
    if (!positions && name[0] != 'v') continue;
    for (std::size_t k = 0; k < p.count; ++k)
      if (!std::isfinite(d[k])) return fmt("%s of particle %zu is %g", name, k, d[k]);
  }
  for (std::size_t a = 0; a < p.attribute_count; ++a) {
    const std::size_t n = p.count * static_cast<std::size_t>(p.attribute_specs[a].components);
    for (std::size_t k = 0; k < n; ++k)
      if (!std::isfinite(p.attribute_data[a][k]))
        return fmt("attribute '%s' entry %zu is %g", p.attribute_specs[a].name.c_str(), k, p.attribute_data[a][k]);
  }
  return "";
}

// --------------------------------------------------------------------------------------------
// Generic checks

Result check_load(const Subject& s) {
  boost::dll::shared_library lib;
  try {
    lib.load(s.file, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    return fail(std::string("cannot be loaded as a shared library: ") + e.what());
  }
  if (!lib.has(plugin_entry_symbol))
    return fail(std::string("not a gdsmc plugin: it exports no '") + plugin_entry_symbol +
                "' (register the plugin with GDSMC_PLUGIN(...))");
  const PluginEntry* entry = lib.get_alias<const PluginEntry*()>(plugin_entry_symbol)();
  if (!entry) return fail("its plugin entry point returned null");
  if (entry->magic != plugin_magic) return fail(fmt("its plugin entry has the wrong magic number 0x%08x", entry->magic));
  return pass("loads with every symbol resolved (rtld_now) and exports the gdsmc plugin entry");
}

Result check_abi(const Subject& s) {
  boost::dll::shared_library lib(s.file, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  const PluginEntry* entry = lib.get_alias<const PluginEntry*()>(plugin_entry_symbol)();
  const std::string versions = fmt("plugin built against SDK ABI %u.%u, this host has SDK ABI %u.%u", entry->abi_major,
                                   entry->abi_minor, sdk_abi_major, sdk_abi_minor);
  if (entry->abi_major != sdk_abi_major)
    return fail("wrong ABI version: " + versions + " (the major versions must be equal; rebuild the plugin against this SDK)");
  if (entry->abi_minor > sdk_abi_minor)
    return fail("wrong ABI version: " + versions + " (the plugin is newer than the host)");
  if (entry->fingerprint != abi_fingerprint())
    return fail("ABI layout fingerprint differs (" + versions +
                "): built with another compiler, standard library or SDK layout");
  return pass(versions + "; layout fingerprint matches");
}

bool good_identifier(const std::string& n) {
  if (n.empty()) return false;
  for (char c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

Result check_descriptor(const Subject& s) {
  LoadedPlugin lp = load_plugin(s.file);
  const PluginDescriptor& d = *lp.descriptor;
  std::vector<std::string> problems;
  const int k = static_cast<int>(d.kind);
  if (k < 1 || k > 5) problems.push_back(fmt("kind %d is not a plugin kind", k));
  if (!good_identifier(d.name)) problems.push_back("name '" + d.name + "' is not a plain identifier (letters, digits, _ or -)");
  if (d.version.empty()) problems.push_back("no version");
  if (d.summary.empty()) problems.push_back("no summary");
  if (d.summary.find('\n') != std::string::npos) problems.push_back("the summary is more than one line");
  if (d.documentation.empty()) problems.push_back("no documentation");
  if (!d.create) problems.push_back("no factory");
  if (!problems.empty()) return fail("descriptor incomplete: " + joined(problems));
  return pass(fmt("%s plugin '%s' version %s: name, summary, documentation (%zu characters), factory",
                  to_string(d.kind), d.name.c_str(), d.version.c_str(), d.documentation.size()));
}

Result check_schema(const Subject& s) {
  const auto& specs = s.desc().parameters;
  std::vector<std::string> problems;
  std::set<std::string> names;
  const std::vector<std::string> reserved = {"plugin", "name", "sample_every", "record_every"};
  for (const auto& p : specs) {
    const std::string who = "parameter '" + p.name + "'";
    if (p.name.empty()) problems.push_back("a parameter has an empty name");
    else if (!good_identifier(p.name)) problems.push_back(who + ": the name is not a plain identifier");
    if (!names.insert(p.name).second) problems.push_back(who + " is declared twice");
    if (std::find(reserved.begin(), reserved.end(), p.name) != reserved.end())
      problems.push_back(who + ": the name is reserved by the pipeline");
    if (p.doc.empty()) problems.push_back(who + " has no documentation");
    if ((p.min || p.max) && p.type != ParamType::real && p.type != ParamType::integer)
      problems.push_back(who + ": a range on a parameter that is not a number");
    if (p.min && p.max && (*p.min > *p.max || (*p.min == *p.max && !(p.min_inclusive && p.max_inclusive))))
      problems.push_back(who + ": the range " + p.range_text() + " is empty");
    if (p.dimension != Dimension::none && p.type != ParamType::real)
      problems.push_back(who + ": a unit on a parameter that is not real");
    if (p.type == ParamType::choice) {
      if (p.choices.empty()) problems.push_back(who + ": a choice with no choices");
      std::set<std::string> c(p.choices.begin(), p.choices.end());
      if (c.size() != p.choices.size()) problems.push_back(who + ": repeated choices");
      if (c.count("")) problems.push_back(who + ": an empty choice");
    }
    if (!p.default_) continue;
    const ParamValue& v = *p.default_;
    bool type_ok = false;
    double x = 0;
    switch (p.type) {
      case ParamType::real:
        if (auto d = std::get_if<double>(&v)) type_ok = true, x = *d;
        if (auto i = std::get_if<std::int64_t>(&v)) type_ok = true, x = static_cast<double>(*i);
        break;
      case ParamType::integer:
        if (auto i = std::get_if<std::int64_t>(&v)) type_ok = true, x = static_cast<double>(*i);
        break;
      case ParamType::boolean: type_ok = std::holds_alternative<bool>(v); break;
      case ParamType::string: type_ok = std::holds_alternative<std::string>(v); break;
      case ParamType::choice:
        type_ok = std::holds_alternative<std::string>(v);
        if (type_ok && std::find(p.choices.begin(), p.choices.end(), std::get<std::string>(v)) == p.choices.end())
          problems.push_back(who + ": the default '" + std::get<std::string>(v) + "' is not one of its choices");
        break;
    }
    if (!type_ok) {
      problems.push_back(who + ": the default " + value_text(v) + " is not of type " + to_string(p.type));
      continue;
    }
    if (p.type == ParamType::real && !std::isfinite(x)) problems.push_back(who + ": the default is not finite");
    if (p.type == ParamType::real || p.type == ParamType::integer) {
      const bool low = p.min && (p.min_inclusive ? x < *p.min : x <= *p.min);
      const bool high = p.max && (p.max_inclusive ? x > *p.max : x >= *p.max);
      if (low || high) problems.push_back(who + ": the default " + value_text(v) + " is outside its range " + p.range_text());
    }
  }
  if (!problems.empty()) return fail("parameter schema not well-formed: " + joined(problems));
  return pass(fmt("%zu parameters: names unique, documented, defaults typed and within their ranges", specs.size()));
}

// Build the plugin in a small pipeline and (when the host can run it) take a few steps.
Result check_defaults(const Subject& s) {
  const Assignment a = base_assignment(s);
  std::unique_ptr<Pipeline> p;
  try {
    p = load_test_pipeline(s, a);
  } catch (const PipelineError& e) {
    auto own = own_errors(e, s.kind());
    return fail("does not construct from its defaults (" + describe_assignment(s, a) + "): " +
                joined(own.empty() ? e.messages() : own));
  }
  if (s.kind() == PluginKind::boundary)
    return pass("constructs from " + describe_assignment(s, a) + " (not stepped: the host runs homogeneous systems only)");
  Engine engine(*p);
  constexpr int steps = 10;
  for (int k = 0; k < steps; ++k) engine.step();
  const double T = engine.context().global ? engine.context().global->temperature : 0;
  const std::string bad = nonfinite_in(engine.particles());
  if (!bad.empty()) return fail("after a few steps of a pipeline with its defaults the state is not finite: " + bad);
  if (!(T > 0) || !std::isfinite(T)) return fail(fmt("after a few steps with its defaults the temperature is %g", T));
  return pass(fmt("constructs from %s; a %zu-particle pipeline sets up and runs %d steps", describe_assignment(s, a).c_str(),
                  p->particles, steps));
}

struct Variant {
  std::string label;
  Assignment params;
};

// Values at and just inside the declared bounds, every choice and both booleans.
std::vector<Variant> bound_variants(const Subject& s) {
  const Assignment base = base_assignment(s);
  std::vector<Variant> out;
  auto add = [&](const ParamSpec& p, const std::string& value, const std::string& what) {
    Variant v{p.name + " = " + value + " (" + what + ")", base};
    v.params[p.name] = value;
    out.push_back(std::move(v));
  };
  for (const auto& p : s.desc().parameters) {
    if (s.user_params.count(p.name)) continue;  // fixed by --params
    if (p.type == ParamType::real || p.type == ParamType::integer) {
      const bool integer = p.type == ParamType::integer;
      auto inside = [&](double bound, bool inclusive, double dir) {
        if (inclusive) return bound;
        if (integer) return dir > 0 ? std::floor(bound) + 1 : std::ceil(bound) - 1;
        return bound + dir * std::max(1e-6, 1e-6 * std::fabs(bound));
      };
      auto text = [&](double v) { return integer ? fmt("%.0f", v) : num(v); };
      if (p.min) add(p, text(inside(*p.min, p.min_inclusive, +1)), p.min_inclusive ? "lower bound" : "just above the lower bound");
      if (p.max) add(p, text(inside(*p.max, p.max_inclusive, -1)), p.max_inclusive ? "upper bound" : "just below the upper bound");
    } else if (p.type == ParamType::boolean) {
      add(p, "true", "boolean");
      add(p, "false", "boolean");
    } else if (p.type == ParamType::choice) {
      for (const auto& c : p.choices) add(p, quoted(c), "choice");
    }
  }
  return out;
}

struct PairReport {
  std::size_t cases = 0;
  std::string nonfinite, locality, rate;
  double worst_momentum = 0, worst_energy = 0;  // violation / tolerance
  std::string momentum_case, energy_case;
  double momentum_excess = 0, energy_excess = 0;
  double energy_declared_total = 0;
};
PairReport pair_suite(CollisionRule& rule, const std::vector<AttributeSpec>& attributes, std::uint64_t seed,
                      std::size_t random_pairs);
std::string pair_failure(const PairReport& r);

Result check_bounds(const Subject& s) {
  const auto variants = bound_variants(s);
  if (variants.empty()) return pass("no parameter with bounds or choices to vary");
  std::size_t built = 0, refused = 0;
  for (const auto& v : variants) {
    std::unique_ptr<Pipeline> p;
    try {
      p = load_test_pipeline(s, v.params);
    } catch (const PipelineError& e) {
      const auto own = own_errors(e, s.kind());
      const std::string m = joined(own.empty() ? e.messages() : own);
      if (m.find("refused parameter") != std::string::npos) {
        ++refused;
        continue;
      }
      return fail("with " + v.label + ", inside the declared range, the plugin failed instead of constructing or "
                  "refusing the value with a ParameterError: " + m);
    }
    ++built;
    if (s.kind() == PluginKind::collision_rule) {
      auto obj = create_object(*p->collision.plugin, p->collision.params);
      const std::string f = pair_failure(pair_suite(*static_cast<CollisionRule*>(obj.get()), obj->attributes(), s.cfg.seed, 2000));
      if (!f.empty()) return fail("with " + v.label + ": " + f);
    }
  }
  return pass(fmt("%zu values at or inside the bounds: %zu construct%s, %zu refused with a message", variants.size(),
                  built, s.kind() == PluginKind::collision_rule ? " (and collide soundly)" : "", refused));
}

Result expect_refused(const Subject& s, const std::string& param, const std::string& value, const std::string& what,
                      std::string& note) {
  Assignment a = base_assignment(s);
  a[param] = value;
  try {
    (void)load_test_pipeline(s, a);
  } catch (const PipelineError& e) {
    for (const auto& m : own_errors(e, s.kind()))
      if (m.find("'" + param + "'") != std::string::npos || m.find("." + param + ":") != std::string::npos ||
          m.find("." + param + ".") != std::string::npos) {
        note = m;
        return pass("");
      }
    return fail("parameter '" + param + "' = " + value + " (" + what + ") was refused without a message naming it: " +
                joined(e.messages()));
  }
  return fail("parameter '" + param + "' = " + value + " (" + what + ") was accepted");
}

Result check_out_of_range(const Subject& s) {
  std::size_t n = 0;
  std::string note;
  for (const auto& p : s.desc().parameters) {
    if (p.type == ParamType::real || p.type == ParamType::integer) {
      const bool integer = p.type == ParamType::integer;
      auto text = [&](double v) { return integer ? fmt("%.0f", v) : num(v); };
      if (p.min) {
        const double v = p.min_inclusive ? (integer ? std::ceil(*p.min) - 1 : *p.min - std::max(1.0, std::fabs(*p.min))) : *p.min;
        Result r = expect_refused(s, p.name, text(v), "below its range " + p.range_text(), note);
        if (r.status != Status::pass) return r;
        ++n;
      }
      if (p.max) {
        const double v = p.max_inclusive ? (integer ? std::floor(*p.max) + 1 : *p.max + std::max(1.0, std::fabs(*p.max))) : *p.max;
        Result r = expect_refused(s, p.name, text(v), "above its range " + p.range_text(), note);
        if (r.status != Status::pass) return r;
        ++n;
      }
    } else if (p.type == ParamType::choice) {
      Result r = expect_refused(s, p.name, "not_one_of_the_choices", "not a choice", note);
      if (r.status != Status::pass) return r;
      ++n;
    }
  }
  // An unknown parameter must be refused as well.
  {
    Assignment a = base_assignment(s);
    a["no_such_parameter_xyz"] = "1";
    try {
      (void)load_test_pipeline(s, a);
      return fail("an unknown parameter 'no_such_parameter_xyz' was accepted");
    } catch (const PipelineError& e) {
      if (own_errors(e, s.kind()).empty()) return fail("an unknown parameter was refused without a message naming it");
    }
    ++n;
  }
  return pass(fmt("%zu out-of-range, invalid-choice or unknown values refused with a message (e.g. \"%s\")", n,
                  note.empty() ? "unknown parameter" : note.c_str()));
}

Result check_wrong_type(const Subject& s) {
  std::size_t n = 0;
  std::string note;
  for (const auto& p : s.desc().parameters) {
    std::vector<std::string> values;
    switch (p.type) {
      case ParamType::real: values = {"not_a_number", "[1, 2]"}; break;
      case ParamType::integer: values = {"0.5", "not_a_number"}; break;
      case ParamType::boolean: values = {"not_a_boolean", "2"}; break;
      case ParamType::string:
      case ParamType::choice: values = {"[1, 2]", "{a: 1}"}; break;
    }
    for (const auto& v : values) {
      Result r = expect_refused(s, p.name, v, std::string("wrong type for a ") + to_string(p.type), note);
      if (r.status != Status::pass) return r;
      ++n;
    }
  }
  if (n == 0) return pass("no parameters");
  return pass(fmt("%zu values of the wrong type refused with a message (e.g. \"%s\")", n, note.c_str()));
}

bool close(double a, double b, double rel, double abs) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (a == b) return true;
  return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)) + abs;
}

// Compare two diagnostics' outputs; returns "" or where they differ. rel = abs = 0: bitwise.
std::string compare_outputs(const DiagnosticOutput& a, const DiagnosticOutput& b, double rel, double abs) {
  auto vec = [&](const std::string& what, const std::vector<double>& x, const std::vector<double>& y) -> std::string {
    if (x.size() != y.size()) return fmt("%s has %zu values in one run and %zu in the other", what.c_str(), x.size(), y.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
      const bool same = (rel == 0 && abs == 0) ? std::memcmp(&x[k], &y[k], sizeof(double)) == 0 : close(x[k], y[k], rel, abs);
      if (!same) return fmt("%s[%zu] is %.17g in one run and %.17g in the other", what.c_str(), k, x[k], y[k]);
    }
    return "";
  };
  if (a.columns.size() != b.columns.size() || a.arrays.size() != b.arrays.size() ||
      a.histograms.size() != b.histograms.size() || a.scalars.size() != b.scalars.size())
    return "the two runs declared different datasets";
  std::string d;
  for (std::size_t k = 0; k < a.columns.size() && d.empty(); ++k)
    d = vec("series '" + a.columns[k].name + "'", a.columns[k].values, b.columns[k].values);
  for (std::size_t k = 0; k < a.arrays.size() && d.empty(); ++k)
    d = vec("array '" + a.arrays[k].name + "'", a.arrays[k].data, b.arrays[k].data);
  for (std::size_t k = 0; k < a.histograms.size() && d.empty(); ++k) {
    d = vec("histogram '" + a.histograms[k].name + "' edges", a.histograms[k].edges, b.histograms[k].edges);
    if (d.empty()) d = vec("histogram '" + a.histograms[k].name + "'", a.histograms[k].values, b.histograms[k].values);
  }
  for (std::size_t k = 0; k < a.scalars.size() && d.empty(); ++k)
    d = vec("scalar '" + a.scalars[k].name + "'", {a.scalars[k].value}, {b.scalars[k].value});
  return d;
}

std::string compare_particles(const ParticleSpan& a, const ParticleSpan& b) {
  const std::pair<const char*, std::pair<const double*, const double*>> arrays[] = {
      {"x", {a.x, b.x}}, {"y", {a.y, b.y}}, {"z", {a.z, b.z}}, {"vx", {a.vx, b.vx}}, {"vy", {a.vy, b.vy}}, {"vz", {a.vz, b.vz}}};
  for (const auto& [name, d] : arrays)
    for (std::size_t k = 0; k < a.count; ++k)
      if (std::memcmp(&d.first[k], &d.second[k], sizeof(double)) != 0)
        return fmt("%s of particle %zu is %.17g in one run and %.17g in the other", name, k, d.first[k], d.second[k]);
  for (std::size_t at = 0; at < a.attribute_count; ++at) {
    const std::size_t n = a.count * static_cast<std::size_t>(a.attribute_specs[at].components);
    for (std::size_t k = 0; k < n; ++k)
      if (std::memcmp(&a.attribute_data[at][k], &b.attribute_data[at][k], sizeof(double)) != 0)
        return fmt("attribute '%s' entry %zu differs between the runs", a.attribute_specs[at].name.c_str(), k);
  }
  return "";
}

Result check_determinism(const Subject& s) {
  const Assignment a = base_assignment(s);
  constexpr int steps = 20;
  if (s.kind() == PluginKind::boundary) {
    auto run = [&]() {
      auto h = make_harness(s, a, 500);
      auto* b = static_cast<Boundary*>(h->subject.get());
      const ParticleSpan p = h->span();
      for (int k = 0; k < steps; ++k) {
        const double dt = 0.5 * h->sys.time_unit0;
        for (std::size_t i = 0; i < p.count; ++i) {
          p.x[i] += p.vx[i] * dt;
          p.y[i] += p.vy[i] * dt;
          p.z[i] += p.vz[i] * dt;
        }
        h->ctx.dt = dt;
        Rng rng = h->ctx.rng(StreamPurpose::boundary, 0);
        b->apply(h->ctx, p, rng);
        ++h->ctx.step;
      }
      return h;
    };
    auto h1 = run(), h2 = run();
    const std::string d = compare_particles(h1->span(), h2->span());
    if (!d.empty()) return fail("not deterministic: the same seed twice gives different results: " + d);
    return pass(fmt("seed %llu twice: identical particles after %d boundary steps",
                    static_cast<unsigned long long>(s.cfg.seed), steps));
  }
  auto p1 = load_test_pipeline(s, a), p2 = load_test_pipeline(s, a);
  Engine e1(*p1), e2(*p2);
  for (int k = 0; k < steps; ++k) {
    e1.step();
    e2.step();
  }
  std::string d = compare_particles(e1.particles(), e2.particles());
  if (d.empty() && e1.context().collisions != e2.context().collisions)
    d = fmt("%g collisions in one run and %g in the other", e1.context().collisions, e2.context().collisions);
  if (d.empty() && s.kind() == PluginKind::diagnostic)
    d = compare_outputs(e1.diagnostics().at(0), e2.diagnostics().at(0), 0, 0);
  if (!d.empty()) return fail("not deterministic: the same seed twice gives different results: " + d);
  return pass(fmt("seed %llu twice: bit-identical particles%s after %d steps of a %zu-particle pipeline",
                  static_cast<unsigned long long>(s.cfg.seed),
                  s.kind() == PluginKind::diagnostic ? " and output" : "", steps, p1->particles));
}

// --------------------------------------------------------------------------------------------
// Collision rules

struct PairCase {
  Vec3 v1, v2, s;
  const char* what;
};


std::string case_text(const PairCase& c) {
  return fmt("%s pair v1 = %s, v2 = %s, sigma_hat = %s (g.sigma_hat = %.6g)", c.what, vec_text(c.v1).c_str(),
             vec_text(c.v2).c_str(), vec_text(c.s).c_str(), dot(c.v1 - c.v2, c.s));
}

Vec3 gaussian(Rng& rng, double scale) { return {scale * rng.normal(), scale * rng.normal(), scale * rng.normal()}; }

std::vector<PairCase> pair_cases(const CollisionRule& rule, Rng& rng, std::size_t random_pairs) {
  std::vector<PairCase> cases;
  auto forward = [&](const Vec3& g) {
    const double gn = norm(g);
    return gn > 0 ? hard_sphere_impact_direction(g, gn, rng) : rng.unit_vector();
  };
  auto add = [&](Vec3 v1, Vec3 v2, Vec3 s, const char* what) {
    // Directions the kernel never selects (rate 0 on the far side) are flipped.
    if (rule.pair_rate(v1 - v2, s) <= 0 && dot(v1 - v2, s) < 0) s = -1.0 * s;
    cases.push_back({v1, v2, s, what});
  };
  for (std::size_t k = 0; k < random_pairs; ++k) {
    const Vec3 v1 = gaussian(rng, 1), v2 = gaussian(rng, 1);
    if (k % 4 == 3) add(v1, v2, rng.unit_vector(), "random (uniform direction)");
    else add(v1, v2, forward(v1 - v2), "random");
  }
  const std::size_t edge = std::max<std::size_t>(20, random_pairs / 50);
  for (std::size_t k = 0; k < edge; ++k) {
    const Vec3 v = gaussian(rng, 1);
    add(v, v, rng.unit_vector(), "zero-relative-velocity");
    // grazing: sigma_hat nearly perpendicular to g
    const Vec3 v1 = gaussian(rng, 1), v2 = gaussian(rng, 1), g = v1 - v2;
    const Vec3 gh = (1.0 / norm(g)) * g;
    Vec3 t = cross(gh, rng.unit_vector());
    t = (1.0 / norm(t)) * t;
    const double tilt = k % 2 ? 1e-9 : 1e-15;
    const Vec3 sg = t + tilt * gh;
    add(v1, v2, (1.0 / norm(sg)) * sg, "grazing");
    const Vec3 h1 = gaussian(rng, 1e6), h2 = gaussian(rng, 1e6);
    add(h1, h2, forward(h1 - h2), "huge-speed (1e6)");
    const Vec3 t1 = gaussian(rng, 1e-8), t2 = gaussian(rng, 1e-8);
    add(t1, t2, forward(t1 - t2), "tiny-speed (1e-8)");
    const Vec3 u = gaussian(rng, 1e6), gr = gaussian(rng, 1);
    add(u + 0.5 * gr, u - 0.5 * gr, forward(gr), "fast-centre-of-mass (1e6) small-relative-velocity");
    const Vec3 w1 = gaussian(rng, 1), w2 = gaussian(rng, 1);
    add(w1, w2, (1.0 / norm(w1 - w2)) * (w1 - w2), "head-on");
  }
  return cases;
}

PairReport pair_suite(CollisionRule& rule, const std::vector<AttributeSpec>& attributes, std::uint64_t seed,
                      std::size_t random_pairs) {
  const PhiloxKey key = stream_key(seed, 0);
  Rng case_rng(key, StreamPurpose::conformance, 1, 0);
  Rng rule_rng(key, StreamPurpose::conformance, 2, 0);
  const auto cases = pair_cases(rule, case_rng, random_pairs);
  PairReport r;
  ParticleStore store;
  store.allocate(4, attributes);
  const ParticleSpan p = store.span();
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const PairCase& pc = cases[c];
    const std::uint32_t i = c % 2 ? 3 : 0, j = c % 2 ? 1 : 2;  // vary the slots
    const double scale = std::max({norm(pc.v1), norm(pc.v2), 1e-300});
    for (std::size_t k = 0; k < 4; ++k) {
      p.x[k] = case_rng.uniform();
      p.y[k] = case_rng.uniform();
      p.z[k] = case_rng.uniform();
      p.set_velocity(k, gaussian(case_rng, scale));
    }
    p.set_velocity(i, pc.v1);
    p.set_velocity(j, pc.v2);
    for (std::size_t a = 0; a < p.attribute_count; ++a)
      for (std::size_t e = 0; e < 4 * static_cast<std::size_t>(p.attribute_specs[a].components); ++e)
        p.attribute_data[a][e] = scale * case_rng.normal();
    ParticleStore before_store;
    before_store.allocate(4, attributes);
    const ParticleSpan b = before_store.span();
    auto copy_all = [](const ParticleSpan& from, const ParticleSpan& to) {
      for (std::size_t k = 0; k < from.count; ++k) {
        to.x[k] = from.x[k]; to.y[k] = from.y[k]; to.z[k] = from.z[k];
        to.vx[k] = from.vx[k]; to.vy[k] = from.vy[k]; to.vz[k] = from.vz[k];
      }
      for (std::size_t a = 0; a < from.attribute_count; ++a)
        std::copy(from.attribute_data[a], from.attribute_data[a] + from.count * from.attribute_specs[a].components,
                  to.attribute_data[a]);
    };
    copy_all(p, b);

    const Vec3 g = pc.v1 - pc.v2;
    if (r.rate.empty()) {
      const Vec3 other = case_rng.unit_vector();
      for (const Vec3& d : {pc.s, -1.0 * pc.s, other}) {
        const double rate = rule.pair_rate(g, d);
        if (!std::isfinite(rate) || rate < 0) {
          r.rate = fmt("pair_rate(g = %s, sigma_hat = %s) = %g (must be finite and >= 0) for a %s pair", vec_text(g).c_str(),
                       vec_text(d).c_str(), rate, pc.what);
          break;
        }
      }
    }

    const double declared = rule.collide_pair(p, i, j, pc.s, rule_rng);
    ++r.cases;
    const Vec3 w1 = p.velocity(i), w2 = p.velocity(j);
    // finite
    if (r.nonfinite.empty()) {
      std::string bad;
      if (!std::isfinite(declared)) bad = fmt("returned the energy change %g", declared);
      else if (!all_finite(&w1.x, 1) || !all_finite(&w1.y, 1) || !all_finite(&w1.z, 1) || !all_finite(&w2.x, 1) ||
               !all_finite(&w2.y, 1) || !all_finite(&w2.z, 1))
        bad = "produced the velocities " + vec_text(w1) + ", " + vec_text(w2);
      else {
        const std::string n = nonfinite_in(p);
        if (!n.empty()) bad = "produced " + n;
      }
      if (!bad.empty()) r.nonfinite = bad + " for the " + case_text(pc);
    }
    // mass / locality: nothing but the velocities and attributes of i and j may change
    if (r.locality.empty()) {
      for (std::size_t k = 0; k < 4 && r.locality.empty(); ++k) {
        if (p.x[k] != b.x[k] || p.y[k] != b.y[k] || p.z[k] != b.z[k])
          r.locality = fmt("moved particle %zu (a collision changes velocities only)", k);
        else if (k != i && k != j && (p.vx[k] != b.vx[k] || p.vy[k] != b.vy[k] || p.vz[k] != b.vz[k]))
          r.locality = fmt("changed the velocity of particle %zu, which is not in the colliding pair (%u, %u)", k, i, j);
        for (std::size_t a = 0; a < p.attribute_count && r.locality.empty() && k != i && k != j; ++a)
          for (int comp = 0; comp < p.attribute_specs[a].components; ++comp) {
            const std::size_t e = static_cast<std::size_t>(comp) * p.count + k;
            if (std::memcmp(&p.attribute_data[a][e], &b.attribute_data[a][e], sizeof(double)) != 0) {
              r.locality = fmt("changed attribute '%s' of particle %zu, which is not in the colliding pair",
                               p.attribute_specs[a].name.c_str(), k);
              break;
            }
          }
      }
    }
    // momentum
    {
      const Vec3 dp = (w1 + w2) - (pc.v1 + pc.v2);
      const double tol = 64 * kEps * (norm(pc.v1) + norm(pc.v2) + norm(w1) + norm(w2)) + 1e-300;
      const double ratio = std::isfinite(norm(dp)) ? norm(dp) / tol : std::numeric_limits<double>::infinity();
      if (ratio > r.worst_momentum) {
        r.worst_momentum = ratio;
        r.momentum_excess = norm(dp);
        r.momentum_case = case_text(pc) + fmt(": |p' - p| = %.3g, round-off tolerance %.3g", norm(dp), tol);
      }
    }
    // energy
    {
      const double e0 = 0.5 * (dot(pc.v1, pc.v1) + dot(pc.v2, pc.v2));
      const double e1 = 0.5 * (dot(w1, w1) + dot(w2, w2));
      const double diff = (e1 - e0) - declared;
      const double tol = 64 * kEps * (e0 + e1 + std::fabs(declared)) + 1e-300;
      const double ratio = std::isfinite(diff) ? std::fabs(diff) / tol : std::numeric_limits<double>::infinity();
      r.energy_declared_total += declared;
      if (ratio > r.worst_energy) {
        r.worst_energy = ratio;
        r.energy_excess = std::fabs(diff);
        r.energy_case = case_text(pc) + fmt(": actual change of kinetic energy %.10g, declared %.10g (tolerance %.3g)",
                                            e1 - e0, declared, tol);
      }
    }
  }
  return r;
}

std::string pair_failure(const PairReport& r) {
  if (!r.nonfinite.empty()) return "not finite: " + r.nonfinite;
  if (!r.locality.empty()) return "mass: " + r.locality;
  if (r.worst_momentum > 1) return "momentum not conserved: " + r.momentum_case;
  if (r.worst_energy > 1) return "energy change differs from the declared one: " + r.energy_case;
  if (!r.rate.empty()) return "rate: " + r.rate;
  return "";
}

constexpr std::size_t kRandomPairs = 20000;

struct RuleUnderTest {
  std::unique_ptr<Harness> harness;
  CollisionRule* rule = nullptr;
};

RuleUnderTest rule_under_test(const Subject& s) {
  RuleUnderTest r;
  r.harness = make_harness(s, base_assignment(s), 16);
  r.rule = static_cast<CollisionRule*>(r.harness->collision.get());
  return r;
}

Result check_collision_finite(const Subject& s) {
  auto t = rule_under_test(s);
  const PairReport r = pair_suite(*t.rule, t.rule->attributes(), s.cfg.seed, kRandomPairs);
  if (!r.nonfinite.empty()) return fail("NaN or infinity: collide " + r.nonfinite);
  return pass(fmt("%zu pairs (random, zero relative velocity, grazing, speeds 1e6 and 1e-8): velocities, attributes "
                  "and declared energy changes finite", r.cases));
}

Result check_collision_mass(const Subject& s) {
  auto t = rule_under_test(s);
  const PairReport r = pair_suite(*t.rule, t.rule->attributes(), s.cfg.seed, kRandomPairs);
  if (!r.locality.empty()) return fail("mass: collide_pair " + r.locality);
  return pass(fmt("%zu pairs: the particle count is fixed and only the colliding pair changes (mass conserved)", r.cases));
}

Result check_collision_momentum(const Subject& s) {
  auto t = rule_under_test(s);
  const PairReport r = pair_suite(*t.rule, t.rule->attributes(), s.cfg.seed, kRandomPairs);
  if (r.worst_momentum > 1) return fail("momentum not conserved: " + r.momentum_case);
  return pass(fmt("%zu pairs: momentum conserved to round-off (worst %.2g of the tolerance 64 eps |v|)", r.cases,
                  r.worst_momentum));
}

Result check_collision_energy(const Subject& s) {
  auto t = rule_under_test(s);
  const PairReport r = pair_suite(*t.rule, t.rule->attributes(), s.cfg.seed, kRandomPairs);
  if (r.worst_energy > 1) return fail("energy change differs from the declared one: " + r.energy_case);
  return pass(fmt("%zu pairs: the kinetic-energy change equals the declared one to round-off (worst %.2g of the "
                  "tolerance); mean declared change %.4g per random pair", r.cases, r.worst_energy,
                  r.energy_declared_total / static_cast<double>(r.cases)));
}

Result check_collision_rate(const Subject& s) {
  auto t = rule_under_test(s);
  const PairReport r = pair_suite(*t.rule, t.rule->attributes(), s.cfg.seed, kRandomPairs);
  if (!r.rate.empty()) return fail("collision rate invalid: " + r.rate);
  return pass(fmt("pair_rate finite and >= 0 for %zu pairs in 3 directions each", r.cases));
}

Result check_collision_cell(const Subject& s) {
  constexpr std::size_t n = 2000;
  auto h = make_harness(s, base_assignment(s), n);
  Rng attr_rng(h->ctx.key, StreamPurpose::conformance, 3, 0);
  h->randomize_zero_attributes(attr_rng);
  const ParticleSpan p = h->span();
  auto totals = [&](Vec3& mom, double& energy, double& abs_sum) { velocity_totals(p, mom, energy, abs_sum); };
  Vec3 p0, p1;
  double e0, e1, a0, a1;
  totals(p0, e0, a0);
  // dt for about two candidate pairs per particle per call (hard-sphere kernel estimate)
  const double w = 6.0 * M_SQRT2 * std::sqrt(h->global.temperature);
  const double dt = 2.0 * static_cast<double>(n) * 2.0 * h->sys.volume /
                    (static_cast<double>(n) * static_cast<double>(n) * h->sys.sigma * h->sys.sigma * M_PI * w);
  std::uint64_t candidates = 0, accepted = 0;
  double declared = 0;
  for (int k = 0; k < 3; ++k) {
    Rng rng(h->ctx.key, StreamPurpose::collisions, 0, static_cast<std::uint64_t>(k));
    const CellCollision c = h->collide(dt, rng);
    if (c.accepted > c.candidates)
      return fail(fmt("collide_cell reports %llu accepted of %llu candidates", static_cast<unsigned long long>(c.accepted),
                      static_cast<unsigned long long>(c.candidates)));
    if (!std::isfinite(c.energy_change) || !std::isfinite(c.remainder) || !std::isfinite(c.max_rate) || c.max_rate < 0)
      return fail(fmt("collide_cell reports a non-finite or negative result (energy_change %g, remainder %g, max_rate %g)",
                      c.energy_change, c.remainder, c.max_rate));
    candidates += c.candidates;
    accepted += c.accepted;
    declared += c.energy_change;
    const std::string bad = nonfinite_in(p);
    if (!bad.empty()) return fail("not finite after collide_cell: " + bad);
  }
  totals(p1, e1, a1);
  const double ptol = 64 * kEps * (a0 + a1) * std::max(1.0, std::sqrt(static_cast<double>(accepted) / n));
  if (norm(p1 - p0) > ptol)
    return fail(fmt("momentum not conserved by collide_cell on %zu particles: total momentum changed by %s (|dp| = %.3g, "
                    "round-off tolerance %.3g) in %llu collisions", n, vec_text(p1 - p0).c_str(), norm(p1 - p0), ptol,
                    static_cast<unsigned long long>(accepted)));
  const double etol = 64 * kEps * (e0 + e1) * std::max(1.0, static_cast<double>(accepted) / n);
  if (std::fabs((e1 - e0) - declared) > etol)
    return fail(fmt("energy change differs from the declared one in collide_cell: kinetic energy changed by %.10g, "
                    "the rule declared %.10g (tolerance %.3g) over %llu collisions", e1 - e0, declared, etol,
                    static_cast<unsigned long long>(accepted)));
  return pass(fmt("collide_cell on %zu particles: %llu collisions of %llu candidates; momentum conserved (|dp| = %.2g), "
                  "energy change %.6g as declared", n, static_cast<unsigned long long>(accepted),
                  static_cast<unsigned long long>(candidates), norm(p1 - p0), e1 - e0));
}

// --------------------------------------------------------------------------------------------
// Forcings

Result check_forcing_conservation(const Subject& s) {
  constexpr std::size_t n = 1000;
  auto h = make_harness(s, base_assignment(s), n);
  auto* f = static_cast<Forcing*>(h->subject.get());
  const Conservation c = f->conserves();
  const ParticleSpan p = h->span();
  auto totals = [&](Vec3& mom, double& energy, double& abs_sum) { velocity_totals(p, mom, energy, abs_sum); };
  Vec3 p0, p1;
  double e0, e1, a0, a1;
  totals(p0, e0, a0);
  constexpr int steps = 10;
  for (int k = 0; k < steps; ++k) {
    h->update_moments();
    Rng rng = h->ctx.rng(StreamPurpose::forcing, 0);
    f->apply(h->ctx, p, rng);
    h->ctx.time += h->ctx.dt;
    ++h->ctx.step;
    const std::string bad = nonfinite_in(p);
    if (!bad.empty()) return fail(fmt("not finite after %d steps: %s", k + 1, bad.c_str()));
  }
  totals(p1, e1, a1);
  std::vector<std::string> ok;
  if (c.momentum) {
    const double tol = 64 * kEps * (a0 + a1) * steps;
    if (norm(p1 - p0) > tol)
      return fail(fmt("momentum not conserved although conserves() declares it: total momentum changed by %s "
                      "(|dp| = %.3g, tolerance %.3g) in %d steps of dt = %g tau0", vec_text(p1 - p0).c_str(),
                      norm(p1 - p0), tol, steps, kTimeStepTau0));
    ok.push_back(fmt("momentum (|dp| = %.2g)", norm(p1 - p0)));
  }
  if (c.energy) {
    const double tol = 64 * kEps * (e0 + e1) * steps;
    if (std::fabs(e1 - e0) > tol)
      return fail(fmt("energy not conserved although conserves() declares it: kinetic energy changed from %.12g to "
                      "%.12g (tolerance %.3g) in %d steps of dt = %g tau0", e0, e1, tol, steps, kTimeStepTau0));
    ok.push_back(fmt("energy (|dE| = %.2g)", std::fabs(e1 - e0)));
  }
  if (ok.empty())
    return skip(fmt("conserves() declares neither momentum nor energy: nothing to check (the state stayed finite "
                    "over %d steps)", steps));
  return pass("conserves what it declares over " + std::to_string(steps) + " steps: " + joined(ok));
}

Result check_forcing_order(const Subject& s) {
  constexpr std::size_t n = 500;
  auto h = make_harness(s, base_assignment(s), n);
  const Snapshot s0 = h->save();
  const double scale = std::sqrt(h->global.temperature);
  auto run = [&](double dt, int substeps, std::uint32_t unit) {
    h->restore(s0);
    auto obj = h->fresh_subject();
    auto* f = static_cast<Forcing*>(obj.get());
    h->ctx.step = 0;
    h->ctx.time = 0;
    for (int k = 0; k < substeps; ++k) {
      h->update_moments();
      h->ctx.dt = dt;
      Rng rng(h->ctx.key, StreamPurpose::forcing, unit, h->ctx.step);
      f->apply(h->ctx, h->span(), rng);
      h->ctx.time += dt;
      ++h->ctx.step;
    }
    return h->save();
  };
  auto diff = [&](const Snapshot& a, const Snapshot& b) {
    double d = 0;
    for (std::size_t i = 0; i < n; ++i)
      d = std::max({d, std::fabs(a.vx[i] - b.vx[i]), std::fabs(a.vy[i] - b.vy[i]), std::fabs(a.vz[i] - b.vz[i])});
    return d / scale;
  };
  const double dt0 = kTimeStepTau0 * h->sys.time_unit0;
  if (diff(run(dt0, 1, 0), run(dt0, 1, 1u << 16)) > 0)
    return skip("the forcing is stochastic (its result depends on the random stream): the dt-scaling check applies "
                "to deterministic forcings");
  const int order = static_cast<Forcing*>(h->subject.get())->order();
  double D[3];
  for (int k = 0; k < 3; ++k) {
    const double dt = dt0 / std::pow(2.0, k);
    D[k] = diff(run(dt, 1, 0), run(0.5 * dt, 2, 0));
    if (!std::isfinite(D[k])) return fail(fmt("one step of dt = %g tau0 or two of dt/2 gave non-finite velocities", dt / h->sys.time_unit0));
  }
  const double floor = 1e-12;
  const std::string data = fmt("|one step of dt - two of dt/2| / sqrt(T) = %.3g, %.3g, %.3g at dt = %g, %g, %g tau0", D[0],
                               D[1], D[2], kTimeStepTau0, kTimeStepTau0 / 2, kTimeStepTau0 / 4);
  if (order <= 0) {
    if (D[0] > floor) return fail("declares order 0 (exact) but " + data);
    return pass("exact as declared (order 0): " + data);
  }
  if (D[0] <= floor) return pass(fmt("agrees to round-off (better than the declared order %d): ", order) + data);
  const double q = D[2] > floor ? std::log2(D[1] / D[2]) : D[1] > floor ? std::log2(D[0] / D[1]) : INFINITY;
  if (q < order + 1 - 0.3)
    return fail(fmt("declares order %d (one-step error O(dt^%d)) but the difference between one step of dt and two of "
                    "dt/2 scales as dt^%.2f: ", order, order + 1, q) + data);
  return pass(fmt("declared order %d: the one-step difference scales as dt^%.2f (expected >= %d): ", order, q, order + 1) + data);
}

// --------------------------------------------------------------------------------------------
// Boundaries, initial states, diagnostics

Result check_boundary_containment(const Subject& s) {
  constexpr std::size_t n = 1000;
  auto h = make_harness(s, base_assignment(s), n);
  h->sys.geometry = Geometry::slab;
  auto* b = static_cast<Boundary*>(h->subject.get());
  const ParticleSpan p = h->span();
  const double L[3] = {h->sys.box[0], h->sys.box[1], h->sys.box[2]};
  constexpr int steps = 20;
  for (int k = 0; k < steps; ++k) {
    const double dt = 0.5 * h->sys.time_unit0;  // long enough that many particles cross a face
    for (std::size_t i = 0; i < n; ++i) {
      p.x[i] += p.vx[i] * dt;
      p.y[i] += p.vy[i] * dt;
      p.z[i] += p.vz[i] * dt;
    }
    h->ctx.dt = dt;
    h->update_moments();
    Rng rng = h->ctx.rng(StreamPurpose::boundary, 0);
    b->apply(h->ctx, p, rng);
    h->ctx.time += dt;
    ++h->ctx.step;
    const std::string bad = nonfinite_in(p);
    if (!bad.empty()) return fail(fmt("particle lost: after step %d %s", k + 1, bad.c_str()));
    for (std::size_t i = 0; i < n; ++i) {
      const double tol = 1e-9;
      const bool inside = p.x[i] >= -tol * L[0] && p.x[i] <= L[0] * (1 + tol) && p.y[i] >= -0.5 * L[1] * (1 + tol) &&
                          p.y[i] <= 0.5 * L[1] * (1 + tol) && p.z[i] >= -tol * L[2] && p.z[i] <= L[2] * (1 + tol);
      if (!inside)
        return fail(fmt("particle left outside the domain [0, %g] x [-%g, %g] x [0, %g] after step %d: particle %zu at %s",
                        L[0], 0.5 * L[1], 0.5 * L[1], L[2], k + 1, i, vec_text(p.position(i)).c_str()));
    }
  }
  return pass(fmt("%zu particles streamed %d times across the faces: none lost, none left outside the domain", n, steps));
}

Result check_boundary_wall_flux(const Subject&) {
  return skip("goodness-of-fit of the half-range Maxwellian flux emitted by diffuse walls: not available until the SDK "
              "describes walls (temperature, velocity) to the runner");
}

Result check_initial_state(const Subject& s) {
  constexpr std::size_t n = 1000;
  auto h = make_harness(s, base_assignment(s), n);
  const std::string bad = nonfinite_in(h->span());
  if (!bad.empty()) return fail("the generated state is not finite: " + bad);
  const double T = h->global.temperature;
  if (!(T > 0) || !std::isfinite(T)) return fail(fmt("the generated state has temperature %g", T));
  return pass(fmt("%zu particles: finite positions, velocities and attributes; T = %.6g T0, mean velocity %s", n,
                  T / h->sys.initial_temperature,
                  vec_text({h->global.mean_velocity[0], h->global.mean_velocity[1], h->global.mean_velocity[2]}).c_str()));
}

struct DiagnosticRun {
  std::vector<std::string> summary;
  std::unique_ptr<DiagnosticOutput> out;
  std::size_t records = 0;
};

// Feed a fresh diagnostic a fixed sequence of states (optionally with the particles permuted)
// the way the engine does: begin, sample every state, record every other one, finish.
DiagnosticRun run_diagnostic(Harness& h, const std::vector<Snapshot>& states, const std::vector<StepContext>& ctxs,
                             const std::vector<std::uint32_t>* perm) {
  DiagnosticRun r;
  r.out = std::make_unique<DiagnosticOutput>(h.use->instance_name, &r.summary);
  auto obj = h.fresh_subject();
  auto* d = static_cast<Diagnostic*>(obj.get());
  d->begin(h.sys, h.board, *r.out);
  const std::string& name = h.use->plugin->descriptor->name;
  for (std::size_t k = 0; k < states.size(); ++k) {
    h.restore(states[k], perm);
    h.ctx = ctxs[k];
    d->sample(h.ctx, h.span());
    if (k % 2 == 0 || k + 1 == states.size()) {
      r.out->begin_record(h.ctx.time_in_tau0(), h.ctx.collisions_per_particle());
      d->record(h.ctx, *r.out);
      r.out->check_record(name);
      ++r.records;
    }
  }
  d->finish(h.ctx, *r.out);
  return r;
}

struct DiagnosticStates {
  std::unique_ptr<Harness> h;
  std::vector<Snapshot> states;
  std::vector<StepContext> ctxs;
};

DiagnosticStates diagnostic_states(const Subject& s, std::size_t n) {
  DiagnosticStates d;
  d.h = make_harness(s, base_assignment(s), n);
  Harness& h = *d.h;
  Rng attr_rng(h.ctx.key, StreamPurpose::conformance, 4, 0);
  h.randomize_zero_attributes(attr_rng);
  h.update_moments();
  for (int k = 0; k < 7; ++k) {
    d.states.push_back(h.save());
    d.ctxs.push_back(h.ctx);
    const double dt = 0.5 * h.sys.time_unit0;
    Rng rng(h.ctx.key, StreamPurpose::collisions, 0, h.ctx.step);
    h.ctx.dt = dt;
    h.collide(dt, rng);
    h.ctx.time += dt;
    ++h.ctx.step;
  }
  return d;
}

Result check_diagnostic_output(const Subject& s) {
  auto d = diagnostic_states(s, 500);
  DiagnosticRun r;
  try {
    r = run_diagnostic(*d.h, d.states, d.ctxs, nullptr);
  } catch (const std::exception& e) {
    return fail(std::string("malformed output: ") + e.what());
  }
  const DiagnosticOutput& o = *r.out;
  std::vector<std::string> problems;
  for (const auto& c : o.columns) {
    if (c.unit.empty()) problems.push_back("series '" + c.name + "' has no unit");
    if (c.values.size() != r.records)
      problems.push_back(fmt("series '%s' has %zu values after %zu records", c.name.c_str(), c.values.size(), r.records));
  }
  for (const auto& a : o.arrays)
    if (a.unit.empty()) problems.push_back("array '" + a.name + "' has no unit");
  for (const auto& hg : o.histograms) {
    if (hg.edge_unit.empty() || hg.value_unit.empty()) problems.push_back("histogram '" + hg.name + "' lacks a unit");
    if (hg.edges.size() != hg.values.size() + 1) problems.push_back("histogram '" + hg.name + "' edges do not match");
    for (std::size_t k = 1; k < hg.edges.size(); ++k)
      if (!(hg.edges[k] > hg.edges[k - 1])) {
        problems.push_back("histogram '" + hg.name + "' edges are not increasing");
        break;
      }
  }
  for (const auto& sc : o.scalars)
    if (sc.unit.empty()) problems.push_back("scalar '" + sc.name + "' has no unit");
  if (o.columns.empty() && o.arrays.empty() && o.histograms.empty() && o.scalars.empty())
    problems.push_back("it wrote nothing");
  if (!problems.empty()) return fail("malformed output: " + joined(problems));
  return pass(fmt("%zu records: %zu series with one value per record, %zu arrays, %zu histograms, %zu scalars, all with units",
                  r.records, o.columns.size(), o.arrays.size(), o.histograms.size(), o.scalars.size()));
}

// Root-mean-square relative difference over every value two outputs hold (NaN pairs ignored).
double rms_relative_difference(const DiagnosticOutput& a, const DiagnosticOutput& b) {
  double sum = 0;
  std::size_t n = 0;
  auto add = [&](const std::vector<double>& x, const std::vector<double>& y) {
    for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
      if (std::isnan(x[k]) || std::isnan(y[k])) continue;
      const double d = (x[k] - y[k]) / (0.5 * (std::fabs(x[k]) + std::fabs(y[k])) + 1e-12);
      sum += d * d;
      ++n;
    }
  };
  for (std::size_t k = 0; k < std::min(a.columns.size(), b.columns.size()); ++k) add(a.columns[k].values, b.columns[k].values);
  for (std::size_t k = 0; k < std::min(a.arrays.size(), b.arrays.size()); ++k) add(a.arrays[k].data, b.arrays[k].data);
  for (std::size_t k = 0; k < std::min(a.histograms.size(), b.histograms.size()); ++k)
    add(a.histograms[k].values, b.histograms[k].values);
  for (std::size_t k = 0; k < std::min(a.scalars.size(), b.scalars.size()); ++k) add({a.scalars[k].value}, {b.scalars[k].value});
  return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

Result check_diagnostic_order(const Subject& s) {
  constexpr std::size_t n = 500;
  auto d = diagnostic_states(s, n);
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  Rng rng(d.h->ctx.key, StreamPurpose::conformance, 5, 0);
  for (std::size_t k = n - 1; k > 0; --k) std::swap(perm[k], perm[rng.below(static_cast<std::uint32_t>(k + 1))]);
  const DiagnosticRun a = run_diagnostic(*d.h, d.states, d.ctxs, nullptr);
  const DiagnosticRun b = run_diagnostic(*d.h, d.states, d.ctxs, &perm);
  // A diagnostic that draws random numbers (e.g. one that samples pairs) depends on the order
  // only through its random stream: compare the effect of the permutation with that of the seed.
  std::vector<StepContext> reseeded = d.ctxs;
  for (auto& c : reseeded) c.key = stream_key(s.cfg.seed + 1, 7);
  const DiagnosticRun c = run_diagnostic(*d.h, d.states, reseeded, nullptr);
  if (compare_outputs(*a.out, *c.out, 0, 0).empty()) {
    const std::string diff = compare_outputs(*a.out, *b.out, 1e-9, 1e-12);
    if (!diff.empty())
      return fail("values depend on the particle order: with the particles permuted " + diff +
                  " (tolerance: relative 1e-9, absolute 1e-12)");
    return pass(fmt("the same %zu states with the %zu particles in a random order give the same output to round-off",
                    d.states.size(), n));
  }
  const double by_order = rms_relative_difference(*a.out, *b.out);
  const double by_seed = rms_relative_difference(*a.out, *c.out);
  if (!(by_order <= 5 * by_seed + 1e-9))
    return fail(fmt("values depend on the particle order beyond their statistical noise: permuting the particles changes "
                    "the output by %.3g (rms relative), another random stream by %.3g", by_order, by_seed));
  return pass(fmt("stochastic diagnostic (its output depends on its random stream): permuting the %zu particles changes "
                  "the output by %.3g (rms relative), no more than another random stream does (%.3g)", n, by_order,
                  by_seed));
}

// --------------------------------------------------------------------------------------------
// Command line and driver

struct Check {
  std::string name;
  std::function<Result(const Subject&)> run;
};

std::vector<Check> checks_for(PluginKind kind) {
  std::vector<Check> c = {{"parameter_schema", check_schema},
                          {"defaults_construct", check_defaults},
                          {"parameter_bounds", check_bounds},
                          {"out_of_range_rejected", check_out_of_range},
                          {"wrong_type_rejected", check_wrong_type},
                          {"determinism", check_determinism}};
  switch (kind) {
    case PluginKind::collision_rule:
      c.insert(c.end(), {{"collision.finite", check_collision_finite},
                         {"collision.mass", check_collision_mass},
                         {"collision.momentum", check_collision_momentum},
                         {"collision.energy", check_collision_energy},
                         {"collision.rate", check_collision_rate},
                         {"collision.cell", check_collision_cell}});
      break;
    case PluginKind::forcing:
      c.insert(c.end(), {{"forcing.conservation", check_forcing_conservation}, {"forcing.order", check_forcing_order}});
      break;
    case PluginKind::boundary:
      c.insert(c.end(), {{"boundary.containment", check_boundary_containment},
                         {"boundary.wall_flux", check_boundary_wall_flux}});
      break;
    case PluginKind::initial_state: c.push_back({"initial.state", check_initial_state}); break;
    case PluginKind::diagnostic:
      c.insert(c.end(), {{"diagnostic.output", check_diagnostic_output},
                         {"diagnostic.particle_order", check_diagnostic_order}});
      break;
  }
  return c;
}

bool matches(const std::string& pattern, const std::string& name) {
  return name == pattern || name.rfind(pattern + ".", 0) == 0;
}
bool selected(const Config& cfg, const std::string& name) {
  if (cfg.only.empty()) return true;
  for (const auto& o : cfg.only)
    if (matches(o, name)) return true;
  return false;
}

int usage(const std::string& m) {
  std::cerr << "gdsmc conformance: " << m << "\n(see `gdsmc conformance --help`)\n";
  return 2;
}

}  // namespace

int run_conformance(int argc, char** argv) {
  Config cfg;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    auto value = [&](std::string& into) {
      if (const auto eq = a.find('='); eq != std::string::npos && a.rfind("--", 0) == 0) {
        into = a.substr(eq + 1);
        return true;
      }
      if (k + 1 >= argc) return false;
      into = argv[++k];
      return true;
    };
    auto is = [&](const char* opt) { return a == opt || a.rfind(std::string(opt) + "=", 0) == 0; };
    std::string v;
    if (a == "--help" || a == "-h") {
      std::cout << kHelp;
      return 0;
    } else if (a == "--list") {
      cfg.list = true;
    } else if (a == "--no-fork") {
      cfg.fork = false;
    } else if (is("--params")) {
      if (!value(v)) return usage("--params needs a file");
      cfg.params_file = v;
    } else if (is("--context")) {
      if (!value(v)) return usage("--context needs a pipeline file");
      cfg.context_file = v;
    } else if (is("--plugin-path")) {
      if (!value(v)) return usage("--plugin-path needs a directory or file");
      cfg.plugin_paths.emplace_back(v);
    } else if (is("--seed") || is("--timeout")) {
      if (!value(v)) return usage(a + " needs a whole number");
      char* end = nullptr;
      const unsigned long long x = std::strtoull(v.c_str(), &end, 10);
      if (v.empty() || *end) return usage(a + ": '" + v + "' is not a whole number");
      if (is("--seed")) cfg.seed = x;
      else cfg.timeout = static_cast<int>(std::max(1ull, x));
    } else if (is("--only")) {
      if (!value(v)) return usage("--only needs a check name");
      std::stringstream ss(v);
      for (std::string part; std::getline(ss, part, ',');)
        if (!part.empty()) cfg.only.push_back(part);
    } else if (a.size() > 1 && a[0] == '-') {
      return usage("unknown option '" + a + "'");
    } else if (cfg.plugin.empty()) {
      cfg.plugin = a;
    } else {
      return usage("one PLUGIN.so at a time (got '" + cfg.plugin.string() + "' and '" + a + "')");
    }
  }
  if (cfg.plugin.empty()) return usage("give the plugin file to check: gdsmc conformance PLUGIN.so");
  std::error_code ec;
  if (!fs::is_regular_file(cfg.plugin, ec)) return usage(cfg.plugin.string() + ": no such file");

  Subject s;
  s.cfg = cfg;
  s.file = fs::absolute(cfg.plugin);
  // Parameters and context are read up front: a mistake there is the user's, not the plugin's.
  try {
    if (cfg.params_file) {
      const YAML::Node n = YAML::LoadFile(cfg.params_file->string());
      if (n && !n.IsNull()) {
        if (!n.IsMap()) return usage(cfg.params_file->string() + ": expected a mapping of parameter: value");
        for (auto it = n.begin(); it != n.end(); ++it) {
          const std::string key = it->first.Scalar();
          if (key == "plugin" || key == "name") return usage(cfg.params_file->string() + ": '" + key + "' is not a parameter");
          s.user_params[key] = yaml_text(it->second);
        }
      }
    }
    if (cfg.context_file) {
      const YAML::Node n = YAML::LoadFile(cfg.context_file->string());
      if (!n.IsMap()) return usage(cfg.context_file->string() + ": expected a pipeline");
      if (n["initial_state"]) s.context_initial = yaml_text(n["initial_state"]);
      if (n["collision"]) s.context_collision = yaml_text(n["collision"]);
      if (const YAML::Node f = n["forcings"]; f && f.IsSequence())
        for (const auto& e : f) s.context_forcings.push_back(yaml_text(e));
      if (const YAML::Node pl = n["plugins"]; pl && pl.IsSequence())
        for (const auto& e : pl) {
          fs::path d = e.Scalar();
          if (d.is_relative()) d = fs::absolute(*cfg.context_file).parent_path() / d;
          s.context_paths.push_back(d);
        }
    }
  } catch (const YAML::Exception& e) {
    return usage(std::string("cannot read a YAML file: ") + e.what());
  }

  const std::string file_label = "plugin file " + s.file.filename().string();
  auto print = [&](const std::string& check, const Result& r, const std::string& label) {
    std::string m = r.message;
    std::replace(m.begin(), m.end(), '\n', ' ');
    std::printf("%-5s  %-26s %s: %s\n", status_text(r.status), check.c_str(), label.c_str(), m.c_str());
    std::fflush(stdout);
  };
  int failed = 0, passed = 0, skipped = 0;
  auto count = [&](const Result& r) {
    if (r.status == Status::pass) ++passed;
    else if (r.status == Status::skip) ++skipped;
    else ++failed;
  };

  if (!cfg.list)
    std::printf("gdsmc conformance: %s (seed %llu, host %s, SDK ABI %u.%u)\n", s.file.string().c_str(),
                static_cast<unsigned long long>(cfg.seed), version_string, sdk_abi_major, sdk_abi_minor);

  // Stage 1: load, ABI, descriptor, each isolated; the rest needs all three.
  const std::vector<std::pair<std::string, std::function<Result(const Subject&)>>> stages = {
      {"load", check_load}, {"abi_version", check_abi}, {"descriptor", check_descriptor}};
  bool usable = true;
  for (const auto& [name, fn] : stages) {
    Result r;
    if (usable) r = isolated([&, f = fn] { return f(s); }, cfg.fork, cfg.timeout);
    else r = skip("needs a plugin that passes load, abi_version and descriptor");
    if (r.status != Status::pass && r.status != Status::skip) usable = false;
    if (!cfg.list) {
      print(name, r, file_label);
      count(r);
    }
  }
  if (!usable) {
    std::printf("gdsmc conformance: %s: %d passed, %d failed, %d skipped: NOT CONFORMING\n", file_label.c_str(), passed,
                failed, skipped);
    return 1;
  }
  s.loaded = load_plugin(s.file);
  const std::string label = "plugin '" + s.desc().name + "'";
  const auto checks = checks_for(s.kind());
  if (cfg.list) {
    for (const auto& name : {"load", "abi_version", "descriptor"}) std::cout << name << "\n";
    for (const auto& c : checks) std::cout << c.name << "\n";
    return 0;
  }
  for (const auto& o : cfg.only) {
    bool any = o == "load" || o == "abi_version" || o == "descriptor";
    for (const auto& c : checks) any = any || matches(o, c.name);
    if (!any) return usage("--only " + o + ": no such check for a " + to_string(s.kind()) + " plugin (--list lists them)");
  }

  char tmpl[] = "/tmp/gdsmc-conformance-XXXXXX";
  if (const char* t = ::mkdtemp(tmpl)) s.workdir = t;
  else return usage(std::string("cannot create a temporary directory: ") + std::strerror(errno));

  bool constructed = true;
  for (const auto& c : checks) {
    if (!selected(cfg, c.name) && !(c.name == "defaults_construct" && !cfg.only.empty())) continue;
    Result r;
    const bool needs_object = c.name != "parameter_schema" && c.name != "defaults_construct";
    if (needs_object && !constructed) r = skip("needs an object built from the defaults (see defaults_construct)");
    else r = isolated([&] { return c.run(s); }, cfg.fork, cfg.timeout);
    if (c.name == "defaults_construct") {
      constructed = r.status != Status::fail;  // after a crash, let every check show its own crash
      if (!selected(cfg, c.name) && constructed) continue;  // a silent prerequisite of --only
    }
    if (r.status == Status::fail || r.status == Status::crash)
      r.message += fmt(" [reproduce: gdsmc conformance %s --seed %llu --only %s]", s.file.string().c_str(),
                       static_cast<unsigned long long>(cfg.seed), c.name.c_str());
    print(c.name, r, label);
    count(r);
  }
  fs::remove_all(s.workdir, ec);
  std::printf("gdsmc conformance: %s (%s, %s): %d passed, %d failed, %d skipped: %s\n", label.c_str(),
              to_string(s.kind()), s.file.filename().c_str(), passed, failed, skipped,
              failed ? "NOT CONFORMING" : "conforming");
  return failed ? 1 : 0;
}

}  // namespace gdsmc::host
