// Internal to the conformance runner: the types and functions its files share.
#pragma once
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
#include <gdsmc/physics/moments.hpp>

#include "config/params.hpp"
#include "config/pipeline.hpp"
#include "engine/engine.hpp"
#include "engine/majorant.hpp"
#include "engine/particle_store.hpp"
#include "output/diagnostic_output.hpp"
#include "plugins/kinds.hpp"
#include "plugins/loader.hpp"
#include "plugins/registry.hpp"
#include "util/text.hpp"
#include "conformance/harness.hpp"

namespace gdsmc::host::conformance {

namespace fs = std::filesystem;

constexpr double kEps = std::numeric_limits<double>::epsilon();

enum class Status { pass, fail, skip, crash };

struct Result {
  Status status = Status::pass;
  std::string message;
};
inline Result pass(std::string m) { return {Status::pass, std::move(m)}; }
inline Result fail(std::string m) { return {Status::fail, std::move(m)}; }
inline Result skip(std::string m) { return {Status::skip, std::move(m)}; }

using Assignment = std::map<std::string, std::string>;  // parameter -> YAML text of its value

struct Config {
  fs::path plugin;
  std::vector<fs::path> plugin_paths;
  std::vector<fs::path> params_files;  // --params, repeatable: each set is checked in turn
  std::optional<fs::path> params_file, context_file;  // params_file: the set being checked
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
  // The context's system and boundaries (YAML flow text), for plugins that need a slab; empty:
  // a homogeneous system (boundaries: the plugin under test itself in a slab).
  std::string context_system, context_boundaries;
  std::vector<std::string> context_forcings;        // YAML flow text of the context's forcings
  std::vector<fs::path> context_paths;

  const PluginDescriptor& desc() const { return *loaded->descriptor; }
  PluginKind kind() const { return desc().kind; }
};

constexpr double kTimeStepTau0 = 0.05;
constexpr double kDensity = 1.0e-3;

struct PairReport {
  std::size_t cases = 0;
  std::string nonfinite, locality, rate;
  double worst_momentum = 0, worst_energy = 0;  // violation / tolerance
  std::string momentum_case, energy_case;
  double momentum_excess = 0, energy_excess = 0;
  double energy_declared_total = 0;
};

const char* status_text(Status s);
std::string vec_text(const Vec3& v);
Result guarded(const std::function<Result()>& fn);
Result isolated(const std::function<Result()>& fn, bool use_fork, int timeout_seconds);
void velocity_totals(const ParticleSpan& p, Vec3& momentum, double& energy, double& speed_sum);
std::string yaml_text(const YAML::Node& n);
std::string num(double v);
std::string in_range_value(const ParamSpec& s);
Assignment base_assignment(const Subject& s);
std::string describe_assignment(const Subject& s, const Assignment& a);
std::string slot_path(PluginKind k);
const PluginUse& slot(const Pipeline& p, PluginKind k);
// The errors of a refused test pipeline at the subject's slot (by the errors' key path).
std::vector<ConfigError> own_errors(const PipelineError& e, PluginKind k);
// Their printed lines joined by "; ", or every error's when `own` is empty.
std::string error_text(const std::vector<ConfigError>& own, const PipelineError& e);
// The entry that fills a required slot of `kind` (kinds.hpp's stand-in, else the first plugin of
// the kind in `reg` with no required parameters); throws std::runtime_error naming the kind.
std::string stand_in(const PluginRegistry& reg, PluginKind kind);
std::string stand_in_plugin(const PluginKindInfo& info);  // the plugin its stand-in names; "": none
std::string filler(const Subject& s, PluginKind kind);
std::string entry_text(const std::string& plugin, const Assignment& a);
std::unique_ptr<Pipeline> load_test_pipeline(const Subject& s, const Assignment& a, std::size_t particles = 256);
std::unique_ptr<Harness> make_harness(const Subject& s, const Assignment& a, std::size_t n);
std::unique_ptr<SlabHarness> make_slab(const Subject& s, const Assignment& a, std::size_t n = 2000);
bool all_finite(const double* d, std::size_t n);
std::string nonfinite_in(const ParticleSpan& p, bool positions = true);
Result check_load(const Subject& s);
Result check_abi(const Subject& s);
bool good_identifier(const std::string& n);
Result check_descriptor(const Subject& s);
Result check_schema(const Subject& s);
Result check_defaults(const Subject& s);
Result check_bounds(const Subject& s);
Result check_interior(const Subject& s);
Result expect_refused(const Subject& s, const std::string& param, const std::string& value, const std::string& what,
                      std::string& note);
Result check_out_of_range(const Subject& s);
Result check_wrong_type(const Subject& s);
bool close(double a, double b, double rel, double abs);
std::string compare_outputs(const DiagnosticOutput& a, const DiagnosticOutput& b, double rel, double abs);
std::string compare_particles(const ParticleSpan& a, const ParticleSpan& b);
Result check_determinism(const Subject& s);
Result check_threads(const Subject& s);
Result check_checkpoint(const Subject& s);
Vec3 gaussian(Rng& rng, double scale);
// A pair of the collision checks: velocities, impact direction, what kind of pair it is.
struct PairCase {
  Vec3 v1, v2, s;
  const char* what;
  double sigma = 1;  // the diameter handed to the kernel (PairBatch::sigma)
};
std::string case_text(const PairCase& c);
// `random_pairs` random pairs and the edge cases (zero relative velocity, grazing, huge and tiny
// speeds, fast centre of mass, head-on), directions on the side the kernel selects.
std::vector<PairCase> pair_cases(const CollisionRule& rule, Rng& rng, std::size_t random_pairs);
// A random 4-particle state around the pair case: slots i and j hold the pair's velocities.
void fill_case(const ParticleSpan& p, const PairCase& pc, std::uint32_t i, std::uint32_t j, Rng& case_rng);
void copy_all(const ParticleSpan& from, const ParticleSpan& to);
// Mass / locality: nothing but the velocities and attributes of i and j may change (r.locality).
void check_locality(const ParticleSpan& p, const ParticleSpan& b, std::uint32_t i, std::uint32_t j, PairReport& r);
// One collision of slots i and j with the impact direction s, through the rule's pair kernel (a
// batch of one pair, PairBatch::direction); writes the velocities back, returns the declared
// energy change. An empty `tally`: none.
double collide_with_direction(const CollisionRule& rule, const ParticleSpan& p, std::uint32_t i, std::uint32_t j,
                              const Vec3& s, double sigma, Rng& rng, std::vector<double>& tally);
// A fresh collision rule, begun as in a run: after the pipeline's other plugins published (e.g. a
// shear rate), on the system of a 16-particle pipeline. Every check that calls a rule begins it.
struct BegunRule {
  std::shared_ptr<PluginObject> object;
  SystemInfo system;
  CollisionRule& rule() const { return *static_cast<CollisionRule*>(object.get()); }
};
// The rule of p's collision slot; with `species` (kept alive by the caller), begun in a mixture of them.
BegunRule begun_rule(const Pipeline& p, const std::vector<SpeciesInfo>* species = nullptr);
BegunRule begun_rule(const Subject& s);   // the subject with its base assignment

PairReport pair_suite(CollisionRule& rule, const std::vector<AttributeSpec>& attributes, std::uint64_t seed,
                      std::size_t random_pairs);
std::string pair_failure(const PairReport& r);
Result check_collision_finite(const Subject& s);
Result check_collision_mass(const Subject& s);
Result check_collision_momentum(const Subject& s);
Result check_collision_energy(const Subject& s);
Result check_collision_rate(const Subject& s);
Result check_collision_acceptance(const Subject& s);
Result check_collision_cell(const Subject& s);
Result check_collision_species(const Subject& s);
Result check_forcing_conservation(const Subject& s);
Result check_forcing_energy(const Subject& s);
Result check_forcing_expected_energy(const Subject& s);
Result check_forcing_order(const Subject& s);
Result check_boundary_containment(const Subject& s);
Result check_boundary_elastic(const Subject& s);
Result check_boundary_wall_flux(const Subject& s);
Result check_boundary_accommodation(const Subject& s);
Result check_boundary_transfer(const Subject& s);
Result check_initial_state(const Subject& s);
Result check_diagnostic_output(const Subject& s);
double rms_relative_difference(const DiagnosticOutput& a, const DiagnosticOutput& b);
Result check_diagnostic_order(const Subject& s);
Result check_diagnostic_moments_read(const Subject& s);


}  // namespace gdsmc::host::conformance
