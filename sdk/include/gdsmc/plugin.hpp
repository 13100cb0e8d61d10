// gdsmc SDK: the five plugin kinds, the descriptor every plugin binary exports, and the
// registration macro.
#pragma once
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include <boost/dll/alias.hpp>

#include "gdsmc/context.hpp"
#include "gdsmc/output.hpp"
#include "gdsmc/params.hpp"
#include "gdsmc/particles.hpp"
#include "gdsmc/random.hpp"
#include "gdsmc/vec3.hpp"
#include "gdsmc/version.hpp"

namespace gdsmc {

enum class PluginKind : std::uint32_t {
  collision_rule = 1,
  forcing = 2,
  boundary = 3,
  initial_state = 4,
  diagnostic = 5,
};

inline const char* to_string(PluginKind k) {
  switch (k) {
    case PluginKind::collision_rule: return "collision";
    case PluginKind::forcing: return "forcing";
    case PluginKind::boundary: return "boundary";
    case PluginKind::initial_state: return "initial";
    case PluginKind::diagnostic: return "diagnostic";
  }
  return "unknown";
}

// Common base of everything a plugin makes.
class GDSMC_API PluginObject {
 public:
  virtual ~PluginObject() = default;
  // Extra per-particle attributes this object needs the host to store.
  virtual std::vector<AttributeSpec> attributes() const { return {}; }
  // Publish named model quantities (e.g. "restitution") before the run starts.
  virtual void publish(QuantityBoard&) const {}
};

// One cell's collision stage, as the host hands it to a collision rule (000 Eqs. 4.13, 4.23).
struct CellCollision {
  ParticleSpan particles;
  const std::uint32_t* members = nullptr;  // indices of the cell's particles; nullptr: all of them
  std::uint32_t count = 0;                 // N_c
  double volume = 0;                       // cell volume
  double sigma = 1;                        // diameter
  double dt = 0;
  double majorant = 0;                     // w: upper estimate of the acceptance rate in this cell
  double remainder = 0;                    // fractional candidate carried between steps (in/out)
  Rng* rng = nullptr;
  // Results, written by the rule:
  std::uint64_t candidates = 0;
  std::uint64_t accepted = 0;
  std::uint64_t majorant_exceeded = 0;     // candidates whose rate exceeded w (accepted with p = 1)
  double max_rate = 0;                     // largest rate seen (the host raises w from it)
  double energy_change = 0;                // sum over accepted collisions of the declared change of
                                           // kinetic energy (m = 1)
};

class GDSMC_API CollisionRule : public PluginObject {
 public:
  // The whole collision stage of one cell: called once per cell per step.
  virtual void collide_cell(CellCollision& cell) = 0;
  // The collision kernel for one pair, B(g, sigma_hat) >= 0 (the rate per unit solid angle,
  // in units of sigma^2 * speed). For conformance checks and diagnostics, not for the hot loop.
  virtual double pair_rate(const Vec3& g, const Vec3& sigma_hat) const = 0;
  // One collision of particles i and j with impact direction sigma_hat; returns the kinetic
  // energy change the rule declares. For conformance checks, not for the hot loop.
  virtual double collide_pair(const ParticleSpan& particles, std::uint32_t i, std::uint32_t j,
                              const Vec3& sigma_hat, Rng& rng) = 0;
};

// What a forcing promises to conserve (checked by the conformance suite).
struct Conservation {
  bool momentum = false;
  bool energy = false;
};

class GDSMC_API Forcing : public PluginObject {
 public:
  enum class Stage : std::uint32_t {
    before_streaming = 0,  // e.g. shear, drag: acts over the free-streaming stage
    after_collisions = 1,  // e.g. thermostats, stochastic replacement
  };
  virtual Stage stage() const { return Stage::before_streaming; }
  // Update velocities of all particles over ctx.dt. rng is this forcing's stream for this step.
  virtual void apply(const StepContext& ctx, const ParticleSpan& particles, Rng& rng) = 0;
  virtual Conservation conserves() const { return {}; }
  // Order in dt of the integration error of one step (0: exact; used by conformance).
  virtual int order() const { return 1; }
};

class GDSMC_API Boundary : public PluginObject {
 public:
  // Called after free streaming: bring every particle back inside the domain.
  virtual void apply(const StepContext& ctx, const ParticleSpan& particles, Rng& rng) = 0;
};

class GDSMC_API InitialState : public PluginObject {
 public:
  // Fill positions, velocities and declared attributes of all particles.
  virtual void generate(const SystemInfo& system, const ParticleSpan& particles, Rng& rng) = 0;
};

class GDSMC_API Diagnostic : public PluginObject {
 public:
  // Declare series, write constant metadata. Called once before the first step.
  virtual void begin(const SystemInfo& system, const QuantityBoard& quantities, OutputSink& out) = 0;
  // Accumulate from the current state (every `sample_every` steps).
  virtual void sample(const StepContext& ctx, const ParticleSpan& particles) = 0;
  // Append one value to each declared series (every `record_every` steps), usually the mean of
  // the samples since the last record.
  virtual void record(const StepContext& ctx, OutputSink& out) = 0;
  // After the last step: final arrays, scalars and summary lines.
  virtual void finish(const StepContext& ctx, OutputSink& out) { (void)ctx; (void)out; }
};

// Describes a plugin: built once inside the plugin, read by the host after the ABI check.
struct PluginDescriptor {
  PluginKind kind = PluginKind::diagnostic;
  std::string name;
  std::string version;
  std::string summary;        // one line
  std::string documentation;  // paragraphs: physics, equations implemented, outputs
  std::vector<ParamSpec> parameters;
  PluginObject* (*create)(const Params&) = nullptr;  // may throw ParameterError
};

// A fingerprint of what silently breaks layouts between a host and a plugin built apart.
constexpr std::uint64_t abi_fingerprint() {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  mix(sizeof(ParticleSpan));
  mix(sizeof(StepContext));
  mix(sizeof(SystemInfo));
  mix(sizeof(CellCollision));
  mix(sizeof(ParamSpec));
  mix(sizeof(Params));
  mix(sizeof(PluginDescriptor));
  mix(sizeof(std::string));
  mix(sizeof(std::vector<double>));
#if defined(_GLIBCXX_USE_CXX11_ABI)
  mix(_GLIBCXX_USE_CXX11_ABI);
#endif
#if defined(__GNUC__)
  mix(__GNUC__);
#endif
  return h;
}

// The first thing the host reads from a plugin binary: plain data, checked before any C++ object
// crosses the boundary.
struct PluginEntry {
  std::uint32_t magic;  // plugin_magic
  std::uint32_t abi_major;
  std::uint32_t abi_minor;
  std::uint32_t reserved;
  std::uint64_t fingerprint;
  const PluginDescriptor* (*describe)();
};
inline constexpr std::uint32_t plugin_magic = 0x6764736du;  // "gdsm"
inline constexpr const char* plugin_entry_symbol = "gdsmc_plugin_entry";

template <class Rule>
class CollisionRuleAdapter;  // collision.hpp

namespace detail {
template <class T>
PluginObject* create_object(const Params& p) {
  if constexpr (std::is_base_of_v<PluginObject, T>) {
    return new T(p);
  } else {
    return new CollisionRuleAdapter<T>(T(p));
  }
}
template <class T>
constexpr PluginKind kind_of() {
  if constexpr (std::is_base_of_v<Forcing, T>) return PluginKind::forcing;
  else if constexpr (std::is_base_of_v<Boundary, T>) return PluginKind::boundary;
  else if constexpr (std::is_base_of_v<InitialState, T>) return PluginKind::initial_state;
  else if constexpr (std::is_base_of_v<Diagnostic, T>) return PluginKind::diagnostic;
  else return PluginKind::collision_rule;
}
}  // namespace detail

// Builds the descriptor from T's static members: name, version, summary, documentation and
// parameters(). T is a Forcing / Boundary / InitialState / Diagnostic subclass, or a collision
// rule struct (see collision.hpp).
template <class T>
PluginDescriptor describe() {
  PluginDescriptor d;
  d.kind = detail::kind_of<T>();
  d.name = T::name;
  d.version = T::version;
  d.summary = T::summary;
  d.documentation = T::documentation;
  d.parameters = T::parameters();
  d.create = &detail::create_object<T>;
  return d;
}

}  // namespace gdsmc

// Registers T as this shared library's plugin (one per library). Place once, at namespace scope.
#define GDSMC_PLUGIN(T)                                                                            \
  namespace {                                                                                      \
  const ::gdsmc::PluginDescriptor* gdsmc_describe_plugin() {                                      \
    static const ::gdsmc::PluginDescriptor descriptor = ::gdsmc::describe<T>();                   \
    return &descriptor;                                                                            \
  }                                                                                                \
  const ::gdsmc::PluginEntry* gdsmc_plugin_entry_impl() {                                          \
    static const ::gdsmc::PluginEntry entry{::gdsmc::plugin_magic, GDSMC_SDK_ABI_MAJOR,            \
                                            GDSMC_SDK_ABI_MINOR,   0u,                             \
                                            ::gdsmc::abi_fingerprint(), &gdsmc_describe_plugin};  \
    return &entry;                                                                                 \
  }                                                                                                \
  }                                                                                                \
  BOOST_DLL_ALIAS(gdsmc_plugin_entry_impl, gdsmc_plugin_entry)
