// system.species: the species of a granular mixture (issue 33), and the counts they get.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "config/sections.hpp"
#include "config/system_info.hpp"
#include "util/text.hpp"

namespace gdsmc::host {

namespace {

constexpr const char* kSpeciesGrammar =
    "valid: species: [{name: A, mass: m_A, diameter: sigma_A, fraction: x_A}, {name: B, ...}] with masses in units "
    "of m and diameters in units of sigma (both default 1), and either every species a number fraction (summing to "
    "1) or every species a count (summing to run.particles)";

bool valid_name(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; });
}

// One entry: its name, mass, diameter and fraction or count; false if refused (reported).
bool parse_entry(Checker& c, const YAML::Node& e, const std::string& path, SpeciesSpec& s) {
  if (!e.IsMap()) {
    c.error(path, e, "expected a mapping {name: A, mass: m_A, diameter: sigma_A, fraction: x_A}, got " +
                         Checker::describe(e), kSpeciesGrammar);
    return false;
  }
  bool ok = c.check_keys(e, path, {"name", "mass", "diameter", "fraction", "count"});
  s.where = c.where(path, e);
  if (!e["name"] || !e["name"].IsScalar() || !valid_name(e["name"].Scalar())) {
    c.error(path + ".name", e["name"] ? e["name"] : e,
            "each species needs a name: letters, digits and '_', not starting with a digit (e.g. light, heavy, A1)");
    ok = false;
  } else {
    s.name = e["name"].Scalar();
  }
  const auto positive = [&](const char* key, double& out) {
    if (!e[key]) return;
    const std::optional<double> v = c.real(e[key], path + "." + key);
    if (!v) {
      ok = false;
    } else if (!(*v > 0) || !std::isfinite(*v)) {
      c.error(path + "." + key, e[key], fmt("the %s must be a positive finite number (in units of %s), got %g", key,
                                            std::string(key) == "mass" ? "m" : "sigma", *v));
      ok = false;
    } else {
      out = *v;
    }
  };
  positive("mass", s.mass);
  positive("diameter", s.diameter);
  if (e["fraction"] && e["count"]) {
    c.error(path, e, "give either fraction or count, not both", kSpeciesGrammar);
    return false;
  }
  if (e["fraction"]) {
    const std::optional<double> v = c.real(e["fraction"], path + ".fraction");
    if (v && (!(*v > 0) || !(*v < 1))) c.error(path + ".fraction", e["fraction"], fmt("a number fraction must lie in (0, 1), got %g", *v));
    if (!v || !(*v > 0) || !(*v < 1)) return false;
    s.fraction = *v;
  } else if (e["count"]) {
    const std::optional<std::int64_t> v = c.integer(e["count"], path + ".count");
    if (v && *v < 1) c.error(path + ".count", e["count"], fmt("a count must be at least 1, got %lld", static_cast<long long>(*v)));
    if (!v || *v < 1) return false;
    s.count = static_cast<std::uint64_t>(*v);
  } else {
    c.error(path, e, "missing 'fraction' (the number fraction N_s/N) or 'count' (N_s)", kSpeciesGrammar);
    return false;
  }
  return ok;
}

}  // namespace

void parse_species(Checker& c, const YAML::Node& n, Pipeline& p) {
  const std::string path = "system.species";
  if (!n.IsSequence() || n.size() < 2 || n.size() > kMaxSpecies) {
    c.error(path, n,
            n.IsSequence() && n.size() == 1
                ? std::string("a mixture lists two or more species; one species is the default (of mass m and diameter "
                              "sigma): remove system.species, or set system.sigma for another diameter")
                : fmt("expected a list of 2 to %zu species, got ", kMaxSpecies) + Checker::describe(n),
            kSpeciesGrammar);
    return;
  }
  std::vector<SpeciesSpec> species(n.size());
  bool ok = true;
  for (std::size_t k = 0; k < n.size(); ++k) ok = parse_entry(c, n[k], item(path, k), species[k]) && ok;
  if (!ok) return;
  for (std::size_t k = 0; k < species.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (species[j].name == species[k].name) {
        c.error(item(path, k) + ".name", n[k]["name"], "species '" + species[k].name + "' is listed twice");
        return;
      }
  const bool counts = species[0].count > 0;
  for (std::size_t k = 1; k < species.size(); ++k)
    if ((species[k].count > 0) != counts) {
      c.error(item(path, k), n[k], "every species gives a fraction, or every species a count, not a mix of both",
              kSpeciesGrammar);
      return;
    }
  if (counts) {
    std::uint64_t total = 0;
    for (const SpeciesSpec& s : species) total += s.count;
    if (p.particles && total != p.particles) {
      c.error(path, n, fmt("the species' counts sum to %llu, but run.particles is %zu: they must be equal",
                           static_cast<unsigned long long>(total), p.particles));
      return;
    }
    for (SpeciesSpec& s : species) s.fraction = static_cast<double>(s.count) / static_cast<double>(total);
  } else {
    double total = 0;
    for (const SpeciesSpec& s : species) total += s.fraction;
    if (!(std::fabs(total - 1.0) <= 1e-9)) {
      c.error(path, n, fmt("the number fractions sum to %.12g: they must sum to 1", total), kSpeciesGrammar);
      return;
    }
    if (p.particles)
      for (std::size_t k = 0; k < species.size(); ++k)
        if (species_counts(species, p.particles)[k] == 0) {
          c.error(item(path, k) + ".fraction", n[k]["fraction"],
                  fmt("species '%s' would get no particle of run.particles = %zu (fraction %g): use a larger "
                      "fraction or more particles",
                      species[k].name.c_str(), p.particles, species[k].fraction));
          return;
        }
  }
  auto table = std::make_shared<SpeciesTable>();
  table->names.reserve(species.size());
  for (const SpeciesSpec& s : species) table->names.push_back(s.name);
  for (std::size_t k = 0; k < species.size(); ++k)
    table->info.push_back(SpeciesInfo{table->names[k].c_str(), species[k].mass, species[k].diameter, species[k].fraction});
  p.species = std::move(species);
  p.species_table = std::move(table);
}

std::vector<std::size_t> species_counts(const std::vector<SpeciesSpec>& species, std::size_t particles) {
  std::vector<std::size_t> counts(species.size(), 0);
  std::uint64_t given = 0;
  for (std::size_t k = 0; k < species.size(); ++k) given += species[k].count;
  if (given == particles && given > 0) {
    for (std::size_t k = 0; k < species.size(); ++k) counts[k] = species[k].count;
    return counts;
  }
  // Largest remainder: floor(x_s N) each, the particles left to the largest fractional parts (ties
  // to the earlier species), so that the counts sum to N.
  std::size_t assigned = 0;
  std::vector<std::pair<double, std::size_t>> remainder(species.size());
  for (std::size_t k = 0; k < species.size(); ++k) {
    const double exact = species[k].fraction * static_cast<double>(particles);
    counts[k] = static_cast<std::size_t>(std::floor(exact));
    assigned += counts[k];
    remainder[k] = {exact - std::floor(exact), k};
  }
  std::stable_sort(remainder.begin(), remainder.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t r = 0; assigned < particles && r < remainder.size(); ++r, ++assigned) ++counts[remainder[r].second];
  return counts;
}

}  // namespace gdsmc::host
