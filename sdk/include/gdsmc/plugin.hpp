// gdsmc SDK: the five plugin kinds, the descriptor every plugin binary exports, and the
// registration macro.
#pragma once
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <boost/dll/alias.hpp>

#include "gdsmc/context.hpp"
#include "gdsmc/output.hpp"
#include "gdsmc/params.hpp"
#include "gdsmc/particles.hpp"
#include "gdsmc/random.hpp"
#include "gdsmc/state.hpp"
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

// Thread context of every call (CLAP style): [setup] single-threaded, before the first step;
// [step] single-threaded, once per step; [worker] may run concurrently on worker threads with
// other calls of the same object: must not modify the object.

// Common base of everything a plugin makes.
class GDSMC_API PluginObject {
 public:
  virtual ~PluginObject() = default;
  // [setup] Extra per-particle attributes this object needs the host to store.
  virtual std::vector<AttributeSpec> attributes() const { return {}; }
  // [setup] Publish named model quantities (e.g. "restitution") before the run starts.
  virtual void publish(QuantityBoard&) const {}
  // [step] Checkpoints: write every member that changes during the run and that the rest of the
  // run depends on (accumulators, sample counts, adaptive parameters, a reservoir), in a fixed
  // order; load_state reads them back in the same order into an object that was constructed
  // from the same parameters and set up again (begin, bind) but never stepped. Members fixed at
  // setup need not be saved. A plugin with no such members keeps the defaults; `gdsmc
  // conformance` (check `checkpoint`) finds one that forgot a member: its resumed run differs.
  virtual void save_state(StateWriter& out) const { (void)out; }
  virtual void load_state(StateReader& in) { (void)in; }
  // [setup] The capability query (as CLAP's get_extension): a pointer to the interface named `id`
  // that this object offers, or nullptr. Capabilities added after SDK 6.0 arrive this way, as minor
  // versions, so that plugins built before them keep loading; the SDK header that defines an
  // interface names its id (a string "gdsmc.<kind>.<name>"). The pointer must stay valid as long as
  // the object lives.
  virtual const void* extension(const char* id) const { (void)id; return nullptr; }
};

// Extension "gdsmc.diagnostic.bracketed_sampling" (SDK 6.1). A diagnostic that offers it is sampled
// twice on each of its sampled steps, both at t + dt: just before the collision stage
// (StepContext::sample_phase = before_collisions) and just after it (after_collisions), instead of
// once after the step. A moment that the flow or a force builds and the collisions relax (a shear
// stress, a heat flux) is a sawtooth over the step; one sample sits at an end of a tooth, off by
// O(dt) (-nu_eta dt / 2 in eta after the step), and the mean of the two sides of the collision jump
// is the middle of the step, off by O(dt^2). A diagnostic adds both samples of what it computes from
// the state (velocities, positions, ctx.moments) and takes what it derives from event totals per
// unit time in one of them; sums whose statistics count one sample a step weigh each sample by
// bracket_weight(ctx). It offers the extension with
//   const void* extension(const char* id) const override { return gdsmc::offer_bracketed_sampling(id); }
// and the host uses it unless the pipeline says run.sampling: after_step, or nothing but the
// collisions changes the velocities (a homogeneous system without forcings).
inline constexpr const char bracketed_sampling_id[] = "gdsmc.diagnostic.bracketed_sampling";
struct BracketedSampling {
  std::uint32_t version = 1;
};
inline constexpr BracketedSampling bracketed_sampling{};
inline const void* offer_bracketed_sampling(const char* id) {
  return std::string_view(id) == bracketed_sampling_id ? &bracketed_sampling : nullptr;
}
// The weight of one sample in its step, for sums whose statistics count one sample a step
// (histogram counts, particle samples): 1/2 for each sample of a bracketed pair, 1 for a lone one.
inline double bracket_weight(const StepContext& ctx) { return ctx.sample_phase == SamplePhase::after_step ? 1.0 : 0.5; }

// Extension "gdsmc.diagnostic.moments_read" (SDK 6.2): the parts of StepContext::moments that a
// diagnostic's sample reads. The host measures a part only when some diagnostic of the run reads
// it (a diagnostic that does not offer this extension reads the parts of moments_all): the peculiar
// moments are a second pass over every particle, about 5 ns a particle, at every sample. A part
// nobody reads is left NaN (cell_mean_velocity, cells, bin_sums nullptr). `gdsmc conformance`
// (check diagnostic.moments_read) runs the diagnostic on the parts it declares and on all of them
// and asks for the same output.
// Version 2 (SDK 6.6) adds `particles`: 0 when sample() reads nothing of its ParticleSpan (only
// ctx: the moments, cells and bin sums above, the tallies). Such a diagnostic costs a decomposed
// run (`gdsmc run --decompose`) no gather of the particles to rank 0: it is handed an empty span
// there, and conformance (the same check) runs it on an empty span and asks for the same output.
// A diagnostic that reads only the kinetic energy offers it with
//   const void* extension(const char* id) const override {
//     if (const void* e = gdsmc::offer_bracketed_sampling(id)) return e;  // if it offers that too
//     return gdsmc::offer_moments_read<gdsmc::moments_energy>(id);
//   }
// and one that reads the bins' sums and no particle with offer_moments_read<gdsmc::moments_bins,
// gdsmc::reads_no_particles>(id).
inline constexpr const char moments_read_id[] = "gdsmc.diagnostic.moments_read";
struct MomentsRead {
  std::uint32_t version = 2;
  std::uint32_t parts = moments_all;  // MomentsPart bits
  std::uint32_t particles = 1;        // version >= 2: 0 when sample() reads no particle (1 otherwise)
};
inline constexpr bool reads_no_particles = false;
template <std::uint32_t Parts, bool ReadsParticles = true>
inline constexpr MomentsRead moments_read{2, Parts, ReadsParticles ? 1u : 0u};
template <std::uint32_t Parts, bool ReadsParticles = true>
inline const void* offer_moments_read(const char* id) {
  static_assert((Parts & ~static_cast<std::uint32_t>(moments_known)) == 0, "Parts: MomentsPart bits");
  return std::string_view(id) == moments_read_id ? &moments_read<Parts, ReadsParticles> : nullptr;
}

// Extension "gdsmc.species" (SDK 6.5): the plugin handles a mixture (SystemInfo::species): it
// weighs every particle's velocity by its species' mass (momentum m_i v_i, energy m_i v_i^2 / 2,
// temperature m_i <V_i^2> / 3) and reads any per-species parameter it takes. The host refuses a
// pipeline with system.species in which some plugin does not offer it, naming the plugin: a plugin
// written for one species of unit mass would give wrong physics without an error. A one-species run
// never asks. A plugin class offers it with
//   const void* extension(const char* id) const override { return gdsmc::offer_species(id); }
// (chained with its other offers: if (const void* e = gdsmc::offer_species(id)) return e; ...),
// and a collision rule struct by declaring  static constexpr bool species_aware = true;
inline constexpr const char species_id[] = "gdsmc.species";
struct SpeciesSupport {
  std::uint32_t version = 1;
};
inline constexpr SpeciesSupport species_support{};
inline const void* offer_species(const char* id) {
  return std::string_view(id) == species_id ? &species_support : nullptr;
}

// The form of a collision rule's kernel B(g, s) (rate per unit solid angle, in units of
// sigma^2 x speed), which tells the host how to draw candidates for it (000 Eqs. 4.13, 4.23):
//   hard_sphere: B = scale Theta(g.s)(g.s); the host draws P sigma^2 pi W dt / V candidates with
//                W = rate_bound(w) = scale w; a candidate is accepted with probability |g| / w and
//                sigma_hat then drawn from Theta(g.s)(g.s);
//   general:     any B; the host draws P sigma^2 4 pi W dt / V candidates; sigma_hat is drawn
//                uniformly and the pair accepted with probability B(g, s) / W.
enum class KernelForm : std::uint32_t { hard_sphere = 0, general = 1 };

// One batch of candidate pairs of one cell, as the host hands it to a collision rule. The host
// owns the scheme: how many candidates a cell tests, which pairs, the majorant w and its
// updates, remainders, sub-populations and slicing. No particle appears twice in a batch, so the
// pairs may be taken in any order within it; the host takes the batches in order. Host-owned: it
// grows only at its end within a major version.
struct PairBatch {
  std::uint32_t count = 0;            // pairs in the batch
  std::uint32_t cell = 0;             // the cell (layer) they belong to
  const std::uint32_t* i = nullptr;   // storage index of each pair's first particle (attributes,
  const std::uint32_t* j = nullptr;   //   species: ParticleSpan::species_of) and of its second
  Vec3* v1 = nullptr;                 // velocities of the pair (in); after the collision (out,
  Vec3* v2 = nullptr;                 //   read by the host for accepted pairs only)
  const double* u = nullptr;          // acceptance numbers, uniform in [0, 1), one per pair
  // Impact directions given by the caller (conformance): every pair then collides with its own
  // direction, whatever its rate. nullptr in a run: the rule draws them.
  const Vec3* direction = nullptr;
  std::uint8_t* accepted = nullptr;   // out: 1 for a pair that collided, 0 otherwise
  double speed_bound = 0;             // w: the host's majorant of |g| in this cell
  double rate_bound = 0;              // W = CollisionRule::rate_bound(w)
  // Per-pair majorants w_q of |g| (pairs drawn with probability proportional to them), instead of
  // speed_bound for every pair; nullptr: speed_bound. A general kernel then bounds its rate by
  // rate_bound(w_q). The host uses them with the hard-sphere form only.
  const double* speed_bounds = nullptr;
  double sigma = 1;                   // the pairs' diameter
  const ParticleSpan* particles = nullptr;
  Rng* rng = nullptr;                 // the cell's kernel stream at this step (sigma_hat, the rule's
                                      // own draws), continued from batch to batch
  // The rule's tallies (CollisionRule::tallies(), in that order), zeroed by the host per cell:
  // the rule adds each accepted collision's contribution. nullptr when it declares none.
  double* tally = nullptr;
  // Results, added to by the rule:
  std::uint64_t collided = 0;         // pairs accepted
  std::uint64_t exceeded = 0;         // candidates whose rate exceeded the bound (accepted with p = 1)
  double max_rate = 0;                // the largest rate seen, as the speed bound it would need:
                                      // |g| (hard sphere), w rate / W (general); the host raises w
  double energy_change = 0;           // sum of the declared kinetic-energy changes (m_i v_i^2 / 2)
  // Sum over the exceeded candidates of rate / bound - 1: the collisions the bound missed (each
  // was accepted once where its rate asked for more), which the host reports beside `collided`.
  double missed = 0;
};

class GDSMC_API CollisionRule : public PluginObject {
 public:
  // [setup] Called once, after every plugin has published its quantities and before boundaries,
  // the initial state and diagnostics begin: read what the rule needs from the system and the
  // other plugins (e.g. the shear rate of a uniform_shear forcing), refuse a system it cannot
  // serve (throw ParameterError naming the parameter), and publish what it derives (e.g. the
  // contact value chi of an Enskog gas) for the plugins that begin after it.
  virtual void begin(const SystemInfo& system, QuantityBoard& quantities) { (void)system; (void)quantities; }
  // [setup] Names of the per-collision sums the rule accumulates in PairBatch::tally (e.g. the
  // collisional transfer of momentum). The host sums them over cells and steps and hands the
  // running totals to every plugin as StepContext::collision_tallies.
  virtual std::vector<std::string> tallies() const { return {}; }
  // [setup] Look up per-particle attributes once. The host never moves particle storage during a
  // run, so pointers taken here stay valid.
  virtual void bind(const ParticleSpan& particles) = 0;
  // [setup] How the host draws candidates for this rule's kernel (KernelForm).
  virtual KernelForm kernel_form() const = 0;
  // The kernel B(g, sigma_hat) >= 0 for one pair (rate per unit solid angle, in units of
  // sigma^2 * speed). For conformance checks and diagnostics, not for the hot loop.
  virtual double pair_rate(const Vec3& g, const Vec3& sigma_hat) const = 0;
  // An upper bound of pair_rate(g, s) over every direction s and every |g| <= speed: the host's
  // majorant w bounds |g|, and the rule turns it into a bound of its own kernel (hard-sphere
  // kernel of scale c: c * speed; a kernel shifted by a shear, a * sigma, adds that). Checked by
  // conformance (collision.rate).
  virtual double rate_bound(double speed) const = 0;
  // [worker] The pair kernel: accept or reject each candidate of the batch and collide the accepted
  // ones (KernelForm says how). One call per batch; batches of different cells run concurrently,
  // so it must not modify the rule.
  virtual void collide_batch(PairBatch& batch) const = 0;
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
  // [setup] A forcing that is a constant acceleration g (a body force per unit mass) returns true
  // and sets g: the host then integrates it exactly during free flight, x += v t + g t^2/2,
  // v += g t, across wall hits too (004 Eqs. 10-12), and never calls apply().
  virtual bool acceleration(Vec3& g) const { (void)g; return false; }
  // [step] Update velocities of all particles over ctx.dt; ctx.streams are this forcing's
  // streams. Returns the kinetic energy it added to the gas, sum of (m/2)(v'^2 - v^2) (m = 1):
  // the host's energy ledger records it, and conformance checks it against the particles.
  virtual double apply(const StepContext& ctx, const ParticleSpan& particles) = 0;
  virtual Conservation conserves() const { return {}; }
  // Order in dt of the integration error of one step (0: exact; used by conformance). For a
  // stochastic forcing, the weak order of its scheme (1 for Euler-Maruyama white noise).
  virtual int order() const { return 1; }
  // [step] Optional: a stochastic forcing (a white-noise thermostat, random kicks) may declare
  // the kinetic energy per unit time it adds on average over the coming step, given the state
  // `particles` before apply() (m = 1; e.g. 3 N D for white noise of strength D per velocity
  // component). Returns true and sets `rate` if it declares one; conformance then compares the
  // mean measured energy input over many steps with it (forcing.expected_energy).
  virtual bool expected_energy_rate(const StepContext& ctx, const ParticleSpan& particles, double& rate) const {
    (void)ctx; (void)particles; (void)rate;
    return false;
  }
};

// A particle meeting a boundary plane during free flight, as the host's mover hands it over.
struct WallHit {
  std::uint64_t id = 0;      // the particle's identity
  int side = 0;              // -1: the plane y = -Ly/2 (y_min); +1: y = +Ly/2 (y_max)
  Vec3 position{0, 0, 0};    // on the plane (in); for a transfer, the re-entry point (out)
  Vec3 velocity{0, 0, 0};    // at the hit, the acceleration applied up to it (in); after (out)
  double time = 0;           // of the hit (reduced units, from the start of the run)
  double remaining = 0;      // flight time left in this step: the host streams it afterwards
  // [SDK 6.5] The particle's species (SystemInfo::species; 0 in a one-species run): its mass is
  // system.species_mass(species).
  std::uint32_t species = 0;
};

enum class HitResult : std::uint32_t {
  reflected = 0,    // re-emitted into the gas from the same plane: velocity points inward
  transferred = 1,  // re-entered through the opposite plane (periodic, Lees-Edwards):
                    // position.y on that plane, velocity pointing inward from it
};

class GDSMC_API Boundary : public PluginObject {
 public:
  // [setup] Check the run: throw ParameterError (with this plugin's parameter) if the boundary
  // cannot serve it, e.g. Lees-Edwards with a body acceleration.
  virtual void begin(const SystemInfo& system, const QuantityBoard& quantities, const Vec3& body_acceleration) {
    (void)system; (void)quantities; (void)body_acceleration;
  }
  // True for boundaries that transfer particles to the opposite plane (periodic, Lees-Edwards):
  // both y planes must then be this plugin with the same parameters.
  virtual bool transfers() const { return false; }
  // [worker] One interaction, at the exact crossing time; rng is the particle's boundary stream
  // for this step (continued over all its hits in the step). One call per hit, not per particle
  // per step: hits are events, and their physics (a Rayleigh draw, two Gaussians) costs more
  // than the call.
  virtual HitResult interact(const StepContext& ctx, WallHit& hit, Rng& rng) const = 0;
};

class GDSMC_API InitialState : public PluginObject {
 public:
  // [setup] Fill positions, velocities and declared attributes of all particles; streams give
  // each particle its own stream (Streams::for_particle(particles.id[i])); quantities are what
  // the other plugins published (e.g. a Lees-Edwards boundary's "shear_rate").
  virtual void generate(const SystemInfo& system, const QuantityBoard& quantities, const ParticleSpan& particles,
                        const Streams& streams) = 0;
};

class GDSMC_API Diagnostic : public PluginObject {
 public:
  // [setup] Declare series and profiles, write constant metadata.
  virtual void begin(const SystemInfo& system, const QuantityBoard& quantities, OutputSink& out) = 0;
  // [step] Accumulate from the current state (every `sample_every` steps). ctx.moments holds the
  // moments of this state, computed once for every diagnostic.
  virtual void sample(const StepContext& ctx, const ParticleSpan& particles) = 0;
  // [step] Append one value to each declared series (every `record_every` steps), usually the
  // mean of the samples since the last record.
  virtual void record(const StepContext& ctx, OutputSink& out) = 0;
  // [step] After the last step: final arrays, scalars and summary lines.
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

// The interfaces a plugin is compiled against, as text: any change to a virtual signature above
// must be written here too, so that the fingerprint changes with it.
inline constexpr const char abi_interfaces[] =
    "PluginObject{attributes,publish,save_state(StateWriter&)const,load_state(StateReader&),extension(const char*)const};"
    "CollisionRule{begin(SystemInfo,QuantityBoard&),tallies,bind(ParticleSpan),kernel_form,"
    "pair_rate(Vec3,Vec3),rate_bound(double)const,collide_batch(PairBatch&)const};"
    "Forcing{stage,acceleration(Vec3&),apply(StepContext,ParticleSpan)->double,conserves,order,"
    "expected_energy_rate(StepContext,ParticleSpan,double&)const->bool};"
    "Boundary{begin(SystemInfo,QuantityBoard,Vec3),transfers,interact(StepContext,WallHit&,Rng&)const};"
    "InitialState{generate(SystemInfo,QuantityBoard,ParticleSpan,Streams)};"
    "Diagnostic{begin(SystemInfo,QuantityBoard,OutputSink&),sample,record,finish};"
    "OutputSink{series,append,profile,append_profile,array,histogram,scalar,attribute,summary}";

// A fingerprint of what silently breaks layouts between a host and a plugin built apart: struct
// layouts, the standard library's ABI, and the interface text above. It does not name the
// compiler: g++ and clang++ on the same libstdc++ produce the same layouts.
//
// How the contract grows without a major version (SDK 6.0 on):
// - a struct the host owns and hands over by pointer or reference (ParticleSpan, SystemInfo,
//   StepContext, SampledMoments, PairBatch, WallHit) grows only at its end: the fingerprint holds
//   the offset of its last field of 6.0, so an appended field keeps old plugins loading;
// - a struct that is an array element or that plugins build or copy (CellMoments, BoundaryTally,
//   SpeciesInfo, Rng, ParamSpec, PluginDescriptor, ...) is frozen: its size is in the fingerprint;
// - a new capability is an extension (PluginObject::extension), a new virtual of a host-implemented
//   interface (OutputSink) is appended at its end; both are minor versions, and the interface text
//   above stays that of 6.0.
constexpr std::uint64_t abi_fingerprint() {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  // Host-owned, growing at the end: the 6.0 prefix.
  mix(offsetof(ParticleSpan, attribute_data));
  mix(offsetof(SystemInfo, species));
  mix(offsetof(StepContext, quantities));
  mix(offsetof(SampledMoments, kinetic_energy));
  mix(offsetof(PairBatch, missed));
  mix(offsetof(WallHit, remaining));
  // Frozen.
  mix(sizeof(Column<double>));
  mix(sizeof(CellMoments));
  mix(sizeof(VelocityMoments));
  mix(sizeof(BoundaryTally));
  mix(sizeof(EnergyLedgerEntry));
  mix(sizeof(CollisionTally));
  mix(sizeof(SpeciesInfo));
  mix(sizeof(Vec3));
  mix(sizeof(Rng));
  mix(sizeof(Streams));
  mix(sizeof(AttributeSpec));
  mix(sizeof(ParamSpec));
  mix(sizeof(Params));
  mix(sizeof(PluginDescriptor));
  mix(sizeof(std::string));
  mix(sizeof(std::vector<double>));
#if defined(_GLIBCXX_USE_CXX11_ABI)
  mix(_GLIBCXX_USE_CXX11_ABI);
#endif
  for (char c : abi_interfaces) mix(static_cast<unsigned char>(c));
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
// The optional symbol of GDSMC_CONFORMANCE_CONTEXT: a function returning the context's YAML text.
inline constexpr const char* conformance_context_symbol = "gdsmc_conformance_context";

template <class Rule>
class CollisionRuleAdapter;  // collision.hpp
struct PairContext;          // collision.hpp

namespace detail {
template <class R>
concept IsCollisionRuleStruct = requires(const R& r, Vec3& v, const Vec3& s, PairContext& pair) {
  { r.collide(v, v, s, pair) } -> std::convertible_to<double>;
};
template <class T>
PluginObject* create_object(const Params& p) {
  if constexpr (std::is_base_of_v<PluginObject, T>) {
    return new T(p);
  } else {
    return new CollisionRuleAdapter<T>(T(p));
  }
}
template <class T>
constexpr int kind_bases() {
  return int(std::is_base_of_v<CollisionRule, T>) + int(std::is_base_of_v<Forcing, T>) +
         int(std::is_base_of_v<Boundary, T>) + int(std::is_base_of_v<InitialState, T>) +
         int(std::is_base_of_v<Diagnostic, T>);
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
  static_assert(!std::is_base_of_v<PluginObject, T> || detail::kind_bases<T>() == 1,
                "GDSMC_PLUGIN(T): a class deriving from PluginObject must derive from exactly one of "
                "Forcing, Boundary, InitialState, Diagnostic (a collision rule is a plain struct, "
                "see gdsmc/collision.hpp)");
  static_assert(std::is_base_of_v<PluginObject, T> || detail::IsCollisionRuleStruct<T>,
                "GDSMC_PLUGIN(T): T is neither a plugin class nor a collision rule struct with "
                "double collide(Vec3&, Vec3&, const Vec3&, PairContext&) const");
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

// Optional, beside GDSMC_PLUGIN: the pipeline entries `gdsmc conformance` places around this
// plugin when it is checked without --context. TEXT is YAML with any of system, initial_state,
// collision, forcings, boundaries and plugins (as in a pipeline; the plugins it names are looked
// up on the plugin search path, a relative plugins: entry from the library's directory). For a
// plugin that cannot be set up in the default homogeneous gas, e.g. one that needs a slab or a
// plugin publishing 'shear_rate':
//   GDSMC_CONFORMANCE_CONTEXT("forcings: [{plugin: uniform_shear, shear_rate: 0.1}]")
// An optional exported symbol (SDK 6.0): hosts that do not read it load the plugin as before.
#define GDSMC_CONFORMANCE_CONTEXT(TEXT)                                                            \
  namespace {                                                                                      \
  const char* gdsmc_conformance_context_impl() { return TEXT; }                                    \
  }                                                                                                \
  BOOST_DLL_ALIAS(gdsmc_conformance_context_impl, gdsmc_conformance_context)
