// `gdsmc conformance PLUGIN.so`: the plugin conformance runner (see conformance.hpp).
//
// Every check runs in a child process (fork), reports PASS / FAIL / SKIP with a message naming
// the plugin and the property, and a plugin that kills its process yields a CRASH line. Checks
// use the host's own paths: the loader, load_pipeline() on a generated pipeline (the same
// validation a user's pipeline gets) and the Engine, plus direct calls on plugin objects where a
// property needs controlled input (random pairs for a collision rule, permuted particles for a
// diagnostic, one step of dt against two of dt/2 for a forcing).
#include "conformance/conformance.hpp"
#include "conformance/internal.hpp"
#include "util/options.hpp"

namespace gdsmc::host {

using namespace conformance;

namespace {

const char* kHelp = R"(gdsmc conformance PLUGIN.so [options]

Checks one plugin binary against the contract of its kind and prints one line per check:
  PASS | FAIL | SKIP | CRASH   check-name   message naming the plugin and the property
Every check runs in its own process: a plugin that crashes gives a CRASH line, not a dead
runner. Exit status: 0 when nothing failed or crashed, 1 otherwise, 2 for a bad command line.

Checks (by kind):
  all kinds    load, abi_version, descriptor, parameter_schema, defaults_construct,
               parameter_bounds (values at and inside the declared bounds construct or are
               refused with a message), parameter_interior (one parameter at a time at 1/4,
               1/2 and 3/4 of its range, and 3 random points of all the ranges together, drawn
               from the seed: construct or are refused; collision rules must also pass the pair
               checks there), out_of_range_rejected, wrong_type_rejected, determinism,
               threads, checkpoint (a run saved between two records, restored into fresh
               plugin objects and run to its stop gives the bits of the run uninterrupted:
               save_state / load_state keep every member that changes)
  collision    collision.finite, collision.mass, collision.momentum, collision.energy,
               collision.rate (finite, >= 0 and within rate_bound(|g|); on random pairs and
               edge cases: zero relative velocity, grazing, huge and tiny speeds),
               collision.acceptance (collide_batch accepts each candidate with probability
               rate/bound on a grid of relative speeds up to 1.5 times the majorant, tails
               included, and reports the candidates above it), collision.cell (the host's
               collision stage with the rule on a population), collision.species (a rule
               offering gdsmc.species, in a mixture of masses 1 and 3.7, diameters 1 and 2:
               sum m v conserved, the mass-weighted energy change declared, only the pair
               changed; SKIP for a rule without it)
  forcing      forcing.conservation (what conserves() declares), forcing.energy (the energy
               apply() returns equals the measured change), forcing.expected_energy (a
               forcing that declares expected_energy_rate(): the mean measured energy input
               over 400 steps within 4 standard errors of it), forcing.order (one step of dt
               against two of dt/2 scales as dt^(order+1))
  boundary     in a 1x1x1 slab streamed by the host's mover, the plugin on both planes:
               boundary.containment (no particle lost or left outside), boundary.elastic
               (no energy exchanged: every speed kept), boundary.wall_flux (walls: re-emitted
               |v_y|, v_x, v_z against the half-range Maxwellian flux at T_w, chi-square),
               boundary.accommodation (0 specular, 1 diffuse), boundary.transfer (periodic
               types: opposite plane, v_x changed by exactly -+aL)
  initial      initial.state (finite state, positive temperature)
  diagnostic   diagnostic.output (one value per series per record, units given),
               diagnostic.particle_order (values do not depend on the particle order),
               diagnostic.moments_read (with only the parts of ctx.moments it declares,
               the same output to the bit)

Options:
  --params FILE.yaml   parameter values for the plugin (a mapping name: value, units as in a
                       pipeline); required parameters without a default get in-range values.
                       Repeatable: every check runs once per set (the bounds and interior
                       sweeps vary each parameter from the set's values)
  --context FILE.yaml  a pipeline whose initial_state, collision, forcings, system and
                       boundaries entries (and plugins: paths) are used around the plugin, e.g.
                       for a diagnostic that needs the attributes of a particular collision
                       rule, or a slab (default: maxwellian and inelastic_hard_spheres from the
                       plugin search path, a homogeneous system)
  --seed N             seed of every random input (default 1); a failure names it
  --only CHECK         run only CHECK (a name, or a prefix such as 'collision'); repeatable,
                       comma-separated lists allowed
  --plugin-path P      more plugin directories or files (for the context's plugins)
  --list               list the checks that apply to the plugin and exit
  --no-fork            run the checks in this process (for a debugger)
  --timeout S          seconds allowed per check (default 120)
)";
// --------------------------------------------------------------------------------------------
// Command line and driver

struct Check {
  std::string name;
  std::function<Result(const Subject&)> run;
};

// Each kind's own checks, after the common ones.
struct KindChecks {
  PluginKind kind;
  std::vector<Check> checks;
};
const std::vector<KindChecks>& kind_checks() {
  static const std::vector<KindChecks> table = {
      {PluginKind::collision_rule,
       {{"collision.finite", check_collision_finite},
        {"collision.mass", check_collision_mass},
        {"collision.momentum", check_collision_momentum},
        {"collision.energy", check_collision_energy},
        {"collision.rate", check_collision_rate},
        {"collision.acceptance", check_collision_acceptance},
        {"collision.cell", check_collision_cell},
        {"collision.species", check_collision_species}}},
      {PluginKind::forcing,
       {{"forcing.conservation", check_forcing_conservation},
        {"forcing.energy", check_forcing_energy},
        {"forcing.expected_energy", check_forcing_expected_energy},
        {"forcing.order", check_forcing_order}}},
      {PluginKind::boundary,
       {{"boundary.containment", check_boundary_containment},
        {"boundary.elastic", check_boundary_elastic},
        {"boundary.wall_flux", check_boundary_wall_flux},
        {"boundary.accommodation", check_boundary_accommodation},
        {"boundary.transfer", check_boundary_transfer}}},
      {PluginKind::initial_state, {{"initial.state", check_initial_state}}},
      {PluginKind::diagnostic,
       {{"diagnostic.output", check_diagnostic_output},
        {"diagnostic.particle_order", check_diagnostic_order},
        {"diagnostic.moments_read", check_diagnostic_moments_read}}}};
  return table;
}

std::vector<Check> checks_for(PluginKind kind) {
  std::vector<Check> c = {{"parameter_schema", check_schema},
                          {"defaults_construct", check_defaults},
                          {"parameter_bounds", check_bounds},
                          {"parameter_interior", check_interior},
                          {"out_of_range_rejected", check_out_of_range},
                          {"wrong_type_rejected", check_wrong_type},
                          {"determinism", check_determinism},
                          {"threads", check_threads},
                          {"checkpoint", check_checkpoint}};
  for (const auto& row : kind_checks())
    if (row.kind == kind) c.insert(c.end(), row.checks.begin(), row.checks.end());
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

// Options of `gdsmc conformance`, through the host's one option parser (app/cli.hpp).
// Returns -1 to go on, else the exit status (help printed, or a usage error).
int parse_config(int argc, char** argv, Config& cfg) {
  static const std::vector<OptionSpec> specs = {
      {{"--help", "-h"}, ""},  {{"--list"}, ""},
      {{"--no-fork"}, ""},     {{"--params"}, "a file"},
      {{"--context"}, "a pipeline file"}, {{"--plugin-path"}, "a directory or file"},
      {{"--seed"}, "a whole number"},     {{"--timeout"}, "a whole number"},
      {{"--only"}, "a check name"}};
  Args args;
  std::string error;
  if (!parse_args(argc, argv, 1, specs, args, error)) return usage(error);
  if (args.has("--help")) {
    std::cout << kHelp;
    return 0;
  }
  cfg.list = args.has("--list");
  cfg.fork = !args.has("--no-fork");
  for (const auto& v : args.all("--params")) cfg.params_files.emplace_back(v);
  if (args.has("--context")) cfg.context_file = args.all("--context").back();
  for (const auto& v : args.all("--plugin-path")) cfg.plugin_paths.emplace_back(v);
  for (const char* opt : {"--seed", "--timeout"})
    for (const auto& v : args.all(opt)) {
      char* end = nullptr;
      const unsigned long long x = std::strtoull(v.c_str(), &end, 10);
      if (v.empty() || *end) return usage(std::string(opt) + ": '" + v + "' is not a whole number");
      if (std::string(opt) == "--seed") cfg.seed = x;
      else cfg.timeout = static_cast<int>(std::max(1ull, x));
    }
  for (const auto& v : args.all("--only")) {
    std::stringstream ss(v);
    for (std::string part; std::getline(ss, part, ',');)
      if (!part.empty()) cfg.only.push_back(part);
  }
  if (args.positional.size() > 1)
    return usage("one PLUGIN.so at a time (got '" + args.positional[0] + "' and '" + args.positional[1] + "')");
  if (args.positional.empty()) return usage("give the plugin file to check: gdsmc conformance PLUGIN.so");
  cfg.plugin = args.positional[0];
  std::error_code ec;
  if (!fs::is_regular_file(cfg.plugin, ec)) return usage(cfg.plugin.string() + ": no such file");
  return -1;
}

// The entries of a context pipeline (--context, or the one the plugin ships) that surround the
// plugin; a relative plugins: directory is taken from `base`.
void take_context(const YAML::Node& n, const fs::path& base, Subject& s) {
  if (n["initial_state"]) s.context_initial = yaml_text(n["initial_state"]);
  if (n["collision"]) s.context_collision = yaml_text(n["collision"]);
  if (n["system"]) s.context_system = yaml_text(n["system"]);
  if (n["boundaries"]) s.context_boundaries = yaml_text(n["boundaries"]);
  if (const YAML::Node f = n["forcings"]; f && f.IsSequence())
    for (const auto& e : f) s.context_forcings.push_back(yaml_text(e));
  if (const YAML::Node pl = n["plugins"]; pl && pl.IsSequence())
    for (const auto& e : pl) {
      fs::path d = e.Scalar();
      if (d.is_relative()) d = base / d;
      s.context_paths.push_back(d);
    }
}

// Without --context, the context the plugin ships (GDSMC_CONFORMANCE_CONTEXT), if any. Prints the
// context the checks use; returns a failure when the shipped one cannot be read.
Result choose_context(Subject& s) {
  std::string chosen;
  Result r = pass("");
  if (s.cfg.context_file) {
    chosen = "--context " + s.cfg.context_file->string();
  } else if (s.loaded && s.loaded->library->has(conformance_context_symbol)) {
    const char* text = nullptr;
    try {
      text = s.loaded->library->template get_alias<const char*()>(conformance_context_symbol)();
      const YAML::Node n = YAML::Load(text ? text : "");
      if (!n.IsMap()) throw std::runtime_error("expected a mapping of pipeline entries (system, forcings, ...)");
      for (auto it = n.begin(); it != n.end(); ++it) {
        static const std::set<std::string> keys = {"system", "initial_state", "collision", "forcings", "boundaries", "plugins"};
        if (!keys.count(it->first.Scalar()))
          throw std::runtime_error("'" + it->first.Scalar() + "' is not a context entry (valid: system, initial_state, "
                                   "collision, forcings, boundaries, plugins)");
      }
      take_context(n, s.file.parent_path(), s);
      chosen = "shipped by the plugin (GDSMC_CONFORMANCE_CONTEXT): " + yaml_text(n);
    } catch (const std::exception& e) {
      r = fail(std::string("plugin '") + s.desc().name + "': its GDSMC_CONFORMANCE_CONTEXT cannot be used: " + e.what() +
               "; the checks run in the default context");
      chosen = "the default (the shipped one is refused)";
    }
  } else {
    std::vector<std::string> stand_ins;
    for (const PluginKindInfo& row : kPluginKinds)
      if (row.stand_in) stand_ins.push_back(stand_in_plugin(row));
    chosen = "the default: a homogeneous system (a boundary: a slab between two of its planes), the other slots "
             "filled from the plugin search path (" + join(stand_ins, ", ") + ")";
  }
  std::printf("gdsmc conformance: context: %s\n", chosen.c_str());
  return r;
}

// --params and --context. Returns -1 to go on, else the exit status of a usage error.
int read_inputs(const Config& cfg, Subject& s, std::vector<Assignment>& param_sets) {
  // Parameters and context are read up front: a mistake there is the user's, not the plugin's.
  try {
    for (const auto& file : cfg.params_files) {
      Assignment set;
      const YAML::Node n = YAML::LoadFile(file.string());
      if (n && !n.IsNull()) {
        if (!n.IsMap()) return usage(file.string() + ": expected a mapping of parameter: value");
        for (auto it = n.begin(); it != n.end(); ++it) {
          const std::string key = it->first.Scalar();
          if (key == "plugin" || key == "name") return usage(file.string() + ": '" + key + "' is not a parameter");
          set[key] = yaml_text(it->second);
        }
      }
      param_sets.push_back(std::move(set));
    }
    if (cfg.context_file) {
      const YAML::Node n = YAML::LoadFile(cfg.context_file->string());
      if (!n.IsMap()) return usage(cfg.context_file->string() + ": expected a pipeline");
      take_context(n, fs::absolute(*cfg.context_file).parent_path(), s);
    }
  } catch (const YAML::Exception& e) {
    return usage(std::string("cannot read a YAML file: ") + e.what());
  }

  return -1;
}

// The result lines and their counts.
struct Tally {
  int failed = 0, passed = 0, skipped = 0;
  void print(const std::string& check, const Result& r, const std::string& label) const {
    std::string m = r.message;
    std::replace(m.begin(), m.end(), '\n', ' ');
    std::printf("%-5s  %-26s %s: %s\n", status_text(r.status), check.c_str(), label.c_str(), m.c_str());
    std::fflush(stdout);
  }
  void count(const Result& r) {
    if (r.status == Status::pass) ++passed;
    else if (r.status == Status::skip) ++skipped;
    else ++failed;
  }
};

// Stage 1: load, ABI, descriptor, each isolated; the rest needs all three. Returns whether the plugin is usable.
bool run_stage1(const Subject& s, Tally& tally, const std::string& file_label) {
  const Config& cfg = s.cfg;
  const std::vector<std::pair<std::string, std::function<Result(const Subject&)>>> stages = {
      {"load", check_load}, {"abi_version", conformance::check_abi}, {"descriptor", check_descriptor}};
  bool usable = true;
  for (const auto& [name, fn] : stages) {
    Result r;
    if (usable) r = isolated([&, f = fn] { return f(s); }, cfg.fork, cfg.timeout);
    else r = skip("needs a plugin that passes load, abi_version and descriptor");
    if (r.status != Status::pass && r.status != Status::skip) usable = false;
    if (!cfg.list) {
      tally.print(name, r, file_label);
      tally.count(r);
    }
  }
  return usable;
}

// A word for a shell: quoted unless it is plain.
std::string shell_word(const std::string& w) {
  const bool plain = !w.empty() && std::all_of(w.begin(), w.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("/._-+=:,@%", c);
  });
  if (plain) return w;
  std::string q = "'";
  for (char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The command that repeats one check: every option that shaped it (--params of the set being
// checked, --context, --plugin-path, --seed, --timeout).
std::string reproduce_line(const Subject& s, const std::string& check) {
  const Config& cfg = s.cfg;
  std::string line = "gdsmc conformance " + shell_word(s.file.string());
  if (cfg.params_file) line += " --params " + shell_word(fs::absolute(*cfg.params_file).string());
  if (cfg.context_file) line += " --context " + shell_word(fs::absolute(*cfg.context_file).string());
  for (const auto& p : cfg.plugin_paths) line += " --plugin-path " + shell_word(fs::absolute(p).string());
  line += fmt(" --seed %llu", static_cast<unsigned long long>(cfg.seed));
  if (cfg.timeout != 120) line += fmt(" --timeout %d", cfg.timeout);
  return line + " --only " + check;
}

// The checks of the plugin's kind (those selected by --only), each isolated.
void run_checks(const Subject& s, const std::vector<Check>& checks, Tally& tally, const std::string& label) {
  const Config& cfg = s.cfg;
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
      r.message += " [reproduce: " + reproduce_line(s, c.name) + "]";
    tally.print(c.name, r, label);
    tally.count(r);
  }
}

}  // namespace

int run_conformance(int argc, char** argv) {
  Config cfg;
  if (const int status = parse_config(argc, argv, cfg); status >= 0) return status;
  Subject s;
  s.cfg = cfg;
  s.file = fs::absolute(cfg.plugin);
  std::vector<Assignment> param_sets;
  if (const int status = read_inputs(cfg, s, param_sets); status >= 0) return status;

  const std::string file_label = "plugin file " + s.file.filename().string();
  Tally tally;
  if (!cfg.list)
    std::printf("gdsmc conformance: %s (seed %llu, host %s, SDK ABI %u.%u)\n", s.file.string().c_str(),
                static_cast<unsigned long long>(cfg.seed), version_string, sdk_abi_major, sdk_abi_minor);
  if (!run_stage1(s, tally, file_label)) {
    std::printf("gdsmc conformance: %s: %d passed, %d failed, %d skipped: NOT CONFORMING\n", file_label.c_str(),
                tally.passed, tally.failed, tally.skipped);
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

  if (const Result r = choose_context(s); r.status != Status::pass) {
    tally.print("context", r, label);
    tally.count(r);
  }
  char tmpl[] = "/tmp/gdsmc-conformance-XXXXXX";
  if (const char* t = ::mkdtemp(tmpl)) s.workdir = t;
  else return usage(std::string("cannot create a temporary directory: ") + std::strerror(errno));
  if (param_sets.empty()) {
    run_checks(s, checks, tally, label);
  } else {
    // Every set in turn, each with its own --params in the reproduce line.
    for (std::size_t k = 0; k < param_sets.size(); ++k) {
      s.user_params = param_sets[k];
      s.cfg.params_file = cfg.params_files[k];
      std::string set_label = label;
      if (param_sets.size() > 1) {
        set_label += " with --params " + cfg.params_files[k].filename().string();
        std::printf("gdsmc conformance: parameter set %zu of %zu: %s\n", k + 1, param_sets.size(),
                    cfg.params_files[k].string().c_str());
      }
      run_checks(s, checks, tally, set_label);
    }
  }
  std::error_code ec;
  fs::remove_all(s.workdir, ec);
  std::printf("gdsmc conformance: %s (%s, %s): %d passed, %d failed, %d skipped: %s\n", label.c_str(),
              to_string(s.kind()), s.file.filename().c_str(), tally.passed, tally.failed, tally.skipped,
              tally.failed ? "NOT CONFORMING" : "conforming");
  return tally.failed ? 1 : 0;
}

}  // namespace gdsmc::host
