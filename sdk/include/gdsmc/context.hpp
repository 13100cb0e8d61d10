// gdsmc SDK: what plugins may read about the system and the current step.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "gdsmc/random.hpp"
#include "gdsmc/vec3.hpp"

namespace gdsmc {

enum class Geometry : std::uint32_t { homogeneous = 0, slab = 1 };

// One species of the gas (a mixture lists several; SystemInfo::species). Mass in units of the
// reference mass m (SystemInfo::mass = 1), diameter in units of the reference diameter sigma.
struct SpeciesInfo {
  const char* name = "";
  double mass = 1;
  double diameter = 1;
  double fraction = 1;  // number fraction N_s / N
};

// Fixed for a run. Reduced units: m = 1, k_B = 1, lengths in the same unit as sigma. Like every
// struct the host hands to plugins it grows only at its end within a major version.
struct SystemInfo {
  std::size_t particles = 0;
  double number_density = 0;       // n (mean)
  double sigma = 1;                // diameter
  double mass = 1;                 // m (always 1 in this version)
  double initial_temperature = 1;  // T0
  double mean_free_path0 = 0;      // lambda0 = 1 / (sqrt(2) pi n sigma^2)   (000 Eq. 4.1)
  double time_unit0 = 0;           // tau0 = lambda0 / sqrt(2 T0 / m)         (000 Eq. 4.1)
  double volume = 0;               // Omega = N / n
  Geometry geometry = Geometry::homogeneous;
  // Box edges Lx, Ly, Lz. Slab: x in [0, Lx) and z in [0, Lz) periodic, y in [-Ly/2, Ly/2]
  // bounded by the y_min and y_max boundaries. Homogeneous: a cube of volume N/n.
  double box[3] = {0, 0, 0};
  std::size_t cells = 1;           // collision cells: the M layers along y (slab)
  std::size_t bins = 1;            // sampling bins of profiles: equal widths Ly/bins along y
  std::uint64_t seed = 0;
  std::uint32_t realization = 0;
  // The layers' edges along y, cells + 1 values from -Ly/2 to +Ly/2; nullptr: M layers of equal
  // width Ly/M. Read them through layer_lower/layer_upper/layer_of, which serve both. The one
  // exception to "fixed for a run": layers sized from the transient (system.layers:
  // {mean_free_paths, after}) are non-null from begin() on and their values change once, between
  // two steps (cells does not); read them at each call.
  const double* layer_edges = nullptr;
  // The species (species_count entries); nullptr: one species of mass `mass` and diameter `sigma`.
  // A mixture (SDK 6.5: system.species) runs only plugins that offer the extension
  // "gdsmc.species" (plugin.hpp); particle i is species ParticleSpan::species_of(i), and species s
  // has mass species_mass(s) and diameter species_diameter(s), in reduced units.
  std::size_t species_count = 1;
  const SpeciesInfo* species = nullptr;

  double species_mass(std::size_t s) const { return species ? species[s].mass * mass : mass; }
  double species_diameter(std::size_t s) const { return species ? species[s].diameter * sigma : sigma; }
  // sigma_ab = (sigma_a + sigma_b) / 2: the contact distance of a pair (additive hard spheres).
  double pair_diameter(std::size_t a, std::size_t b) const {
    return 0.5 * (species_diameter(a) + species_diameter(b));
  }

  double layer_lower(std::size_t I) const {
    return layer_edges ? layer_edges[I] : -0.5 * box[1] + static_cast<double>(I) * uniform_layer_width();
  }
  double layer_upper(std::size_t I) const { return I + 1 == cells ? 0.5 * box[1] : layer_lower(I + 1); }
  double layer_width(std::size_t I) const { return layer_upper(I) - layer_lower(I); }  // delta y_I
  double bin_width() const { return box[1] / static_cast<double>(bins); }
  double bin_centre(std::size_t b) const { return -0.5 * box[1] + (static_cast<double>(b) + 0.5) * bin_width(); }
  double cross_section() const { return box[0] * box[2]; }                      // A of 000 Eq. 4.2
  // The layer / sampling bin holding a position y (clamped into range, y = +Ly/2 in the last one).
  // With uniform layers this is the host's own arithmetic, to the last bit.
  std::size_t layer_of(double y) const {
    if (!layer_edges) return index_along_y(y, cells);
    std::size_t lo = 0, hi = cells;  // the last edge below or at y: edges[lo] <= y < edges[hi]
    while (hi - lo > 1) {
      const std::size_t mid = (lo + hi) / 2;
      if (layer_edges[mid] <= y) lo = mid;
      else hi = mid;
    }
    return lo;
  }
  std::size_t bin_of(double y) const { return index_along_y(y, bins); }
  std::size_t index_along_y(double y, std::size_t divisions) const {
    const double f = (y + 0.5 * box[1]) / box[1] * static_cast<double>(divisions);
    if (!(f > 0)) return 0;
    const auto k = static_cast<std::size_t>(f);
    return k < divisions ? k : divisions - 1;
  }

 private:
  double uniform_layer_width() const { return box[1] / static_cast<double>(cells); }
};

// Velocity moments of a set of particles (000 Eqs. 4.15-4.18); V is the peculiar velocity.
struct VelocityMoments {
  std::size_t count = 0;
  double mean[3] = {0, 0, 0};      // u
  double second[3][3] = {};        // <V_a V_b>
  double temperature = 0;          // T = (m/3) <V^2>                          (000 Eq. 4.15)
  double fourth = 0;               // <V^4>
  double sixth = 0;                // <V^6>
  // a2 = <V^4> / (15 (T/m)^2) - 1                                              (000 Eq. 4.17)
  double a2() const { return fourth / (15.0 * temperature * temperature) - 1.0; }
  // a3 = -<V^6> / (105 (T/m)^3) + 1 + 3 a2                                     (000 Eq. 4.18)
  double a3() const { return -sixth / (105.0 * temperature * temperature * temperature) + 1.0 + 3.0 * a2(); }
};

// Moments of the particles in one cell (000 Eqs. 4.3-4.6): a layer of a slab, or the single cell
// of a homogeneous system.
struct CellMoments {
  std::size_t count = 0;           // N_I
  double number_density = 0;       // n_I = N_I / (A delta y)
  double mean_velocity[3] = {0, 0, 0};  // u_I
  double temperature = 0;          // T_I = (m / 3 N_I) sum (v - u_I)^2 (0 with fewer than 2 particles)
};

// The moments every diagnostic shares at a sampled step, computed once by the host. Peculiar
// velocities are taken relative to the local flow: V_i = v_i - u_I with I the particle's cell
// (homogeneous: the mean of all particles). So in a slab `local.temperature` is T-bar of
// 000 Eq. (4.8), number_density * local.second is the mean pressure tensor P-bar of Eq. (4.9), and
// a2, a3 are the cumulants of the local peculiar velocities.
//
// In a mixture (SDK 6.5) every moment here and in CellMoments weighs a particle by its species'
// mass m_i: the mean velocity is the barycentric one, sum m_i v_i / sum m_i; second is
// sum m_i V_a V_b / N (number_density * second is still the pressure tensor); temperature is
// sum m_i V_i^2 / 3N; fourth and sixth are the means of (m_i V_i^2)^2 and (m_i V_i^2)^3, so that
// a2() and a3() read as above with m = 1; kinetic_energy is sum m_i v_i^2 / 2.
struct SampledMoments {
  VelocityMoments local;           // local.mean: the mean velocity of all particles
  // The fresh mean velocity of every cell that `local` subtracts: u_I at index 3 I + a (cell_count
  // cells); per-particle diagnostics use it to form exactly the same peculiar velocities.
  const double* cell_mean_velocity = nullptr;
  double number_density = 0;       // n-bar
  double kinetic_energy = 0;       // E = (m/2) sum_i v_i^2, laboratory velocities (004 Eq. A1)
  // [SDK 6.6] moments_cells: every cell's fresh moments (cell_count entries, as StepContext::cells
  // but of this state): N_I, n_I, u_I and T_I = (m / 3 N_I) sum (v - u_I)^2 (000 Eqs. 4.4-4.6; 0
  // below 2 particles). nullptr unless some diagnostic reads them.
  const CellMoments* cells = nullptr;
  // [SDK 6.6] moments_bins: the sums of this state's particles in every sampling bin along y
  // (SystemInfo::bins), bin_sum_stride values a bin in gdsmc::BinSums' order (physics/bins.hpp:
  // 1, v_a, v_a v_b, and with moments_bin_heat |v|^2 v_a); BinSums::append_sample adds them. Each
  // layer's particles are summed in storage order and the layers' sums added in layer order, so a
  // decomposed run (docs/cluster.md) has the same bits. nullptr unless some diagnostic reads them.
  const double* bin_sums = nullptr;
  std::size_t bin_count = 0, bin_sum_stride = 0;
};

// The parts of SampledMoments (SDK 6.2): the host measures those that some diagnostic reads
// (MomentsRead, plugin.hpp) and leaves the others NaN.
enum MomentsPart : std::uint32_t {
  moments_means = 1u << 0,     // local.mean and cell_mean_velocity (local.count, number_density: always)
  moments_energy = 1u << 1,    // kinetic_energy
  moments_peculiar = 1u << 2,  // local.second, local.temperature, local.fourth, local.sixth (a2(), a3())
  // moments_all: the parts of SDK 6.2, what a diagnostic without MomentsRead is given.
  moments_all = moments_means | moments_energy | moments_peculiar,
  moments_cells = 1u << 3,     // [SDK 6.6] cells (each cell's fresh N_I, n_I, u_I, T_I)
  moments_bins = 1u << 4,      // [SDK 6.6] bin_sums: 1, v_a, v_a v_b in every sampling bin
  moments_bin_heat = 1u << 5,  // [SDK 6.6] bin_sums with |v|^2 v_a too (implies moments_bins)
  moments_known = moments_all | moments_cells | moments_bins | moments_bin_heat,
};

// What one boundary (y_min or y_max) has exchanged with the gas since the start of the run: the
// host tallies every interaction from the particle's velocity before and after it.
struct BoundaryTally {
  std::uint64_t hits = 0;
  double momentum[3] = {0, 0, 0};  // sum of m (v_after - v_before): momentum given to the gas
  double energy = 0;               // sum of (m/2)(v_after^2 - v_before^2): energy given to the gas
};

// The kinetic energy each stage has added to the gas since the start of the run (m = 1), so that
// every run can print its energy balance E(t) - E(0) = sum of the stages.
struct EnergyLedgerEntry {
  const char* stage = "";          // "collisions", a forcing's instance name, "y_min", ...
  double energy = 0;
};

// The running total of one of the collision rule's tallies (CollisionRule::tallies): the sum over
// every accepted collision since the start of the run.
struct CollisionTally {
  const char* name = "";
  double value = 0;
};

// Named scalars that plugins publish for each other (e.g. the collision rule publishes
// "restitution"), so that a diagnostic or a forcing can use a model parameter without the user
// repeating it and without the host knowing what it means. Written only before the run starts.
class QuantityBoard {
 public:
  void publish(const std::string& name, double value) { values_[name] = value; }
  const double* find(const std::string& name) const {
    auto it = values_.find(name);
    return it == values_.end() ? nullptr : &it->second;
  }
  const std::map<std::string, double>& all() const { return values_; }

 private:
  std::map<std::string, double> values_;
};

// Where in its step a Diagnostic::sample call sees the state (SDK 6.1; StepContext::sample_phase).
enum class SamplePhase : std::uint32_t {
  after_step = 0,         // after the step's collisions and forcings: a lone sample
  before_collisions = 1,  // a bracketed pair (BracketedSampling, plugin.hpp), both at t + dt: the state
  after_collisions = 2,   //   just before and just after the collision stage
};

// Read-only view of the current step, handed to every plugin call.
struct StepContext {
  const SystemInfo* system = nullptr;
  std::uint64_t step = 0;       // steps completed before this call
  double time = 0;              // reduced units; time / system->time_unit0 is t / tau0
  double dt = 0;                // the step being taken (reduced units)
  std::uint64_t collisions = 0;         // accepted collisions so far
  std::uint64_t candidates = 0;         // candidate pairs tested so far
  std::uint64_t majorant_exceeded = 0;  // candidates whose rate exceeded the cell majorant so far
  double collision_energy_change = 0;   // sum of the kinetic-energy change of every collision so far
  // Per-cell moments (cell_count entries), updated every `run.moments_every` steps (000 Sec.
  // IV.A: "updated every 4 time steps"); sampling never changes them, so diagnostics cannot
  // change the dynamics.
  const CellMoments* cells = nullptr;
  std::size_t cell_count = 0;
  // Moments of all particles as of the same update; in a slab, temperature is T-bar (Eq. 4.8).
  const CellMoments* global = nullptr;
  // Fresh moments of the current state: valid in Diagnostic::sample (nullptr elsewhere).
  const SampledMoments* moments = nullptr;
  // The sum of the constant accelerations that forcings declare (Forcing::acceleration); the
  // host integrates it during free flight.
  Vec3 body_acceleration{0, 0, 0};
  // Boundary tallies: [0] y_min, [1] y_max (slab only; boundary_count = 0 otherwise).
  const BoundaryTally* boundaries = nullptr;
  std::size_t boundary_count = 0;
  // Energy added by each stage so far.
  const EnergyLedgerEntry* energy_ledger = nullptr;
  std::size_t energy_ledger_size = 0;
  // The collision rule's tallies, summed over cells and steps (none for most rules).
  const CollisionTally* collision_tallies = nullptr;
  std::size_t collision_tally_count = 0;
  // True when this step lies in the run's steady averaging window (run.average_after): diagnostics
  // that keep their own steady-state statistics accumulate only then.
  bool in_average_window = false;
  // The random streams of the plugin being called, for this step (set by the host per call).
  const Streams* streams = nullptr;
  // Published model quantities (read-only during the run).
  const QuantityBoard* quantities = nullptr;
  // [SDK 6.1] Diagnostic::sample only: which sample this is (after_step unless the diagnostic offers
  // BracketedSampling). Before the collisions the event totals above (collisions, tallies, the
  // ledger) hold the previous step's; after them, this step's collisions and wall hits but not the
  // forcings that act after the collisions.
  SamplePhase sample_phase = SamplePhase::after_step;
  // [SDK 6.5] A mixture's boundary tallies per species: the tally of species s at boundary b
  // (0: y_min, 1: y_max) at species_boundaries[b * system->species_count + s]; nullptr in a
  // one-species run or a homogeneous system.
  const BoundaryTally* species_boundaries = nullptr;

  // s(t): accepted collisions divided by the number of particles (000, text after Fig. 4); each
  // collision involves two particles, so the mean number of collisions a particle took part in
  // is 2 s.
  double collisions_per_particle() const {
    return system->particles ? static_cast<double>(collisions) / static_cast<double>(system->particles) : 0.0;
  }
  double time_in_tau0() const { return time / system->time_unit0; }
  // The running total of the collision tally `name`, or nullptr if the rule keeps none by that name.
  const double* collision_tally(const std::string& name) const {
    for (std::size_t k = 0; k < collision_tally_count; ++k)
      if (name == collision_tallies[k].name) return &collision_tallies[k].value;
    return nullptr;
  }
};

}  // namespace gdsmc
