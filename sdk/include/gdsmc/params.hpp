// gdsmc SDK: parameter schemas (declared by plugins) and validated parameter values (built by the
// host from the YAML pipeline, with the source location of every value).
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "gdsmc/version.hpp"

namespace gdsmc {

enum class ParamType { real, integer, boolean, string, choice };

// The physical dimension of a real parameter: a product of powers of length, time, temperature
// and mass. The host converts the values a user writes, in reduced units or in the reference units
// (lambda0, sigma, tau0, T0, m and any product of their powers, e.g. {value: 4, unit: T0/tau0})
// into reduced units (m = 1, k_B = 1, sigma, T0) once, at load time; a bare number means the
// reference unit lambda0^length tau0^time T0^temperature m^mass. With k_B = 1 a temperature is an
// energy (mass length^2 / time^2): dimensions are compared after that reduction, so
// {.temperature = 1, .mass = -1, .time = -1} and {.length = 2, .time = -3} are the same.
struct Dimensions {
  int length = 0, time = 0, temperature = 0, mass = 0;
  constexpr bool dimensionless() const { return length == 0 && time == 0 && temperature == 0 && mass == 0; }
  friend constexpr bool operator==(const Dimensions&, const Dimensions&) = default;
};

// Shorthands for common dimensions (the names of SDK 1.x; each is a Dimensions).
enum class Dimension { none, length, time, inverse_time, temperature, velocity, acceleration };

constexpr Dimensions dimensions_of(Dimension d) {
  switch (d) {
    case Dimension::none: return {};
    case Dimension::length: return {1, 0, 0, 0};
    case Dimension::time: return {0, 1, 0, 0};
    case Dimension::inverse_time: return {0, -1, 0, 0};
    case Dimension::temperature: return {0, 0, 1, 0};
    case Dimension::velocity: return {1, -1, 0, 0};
    case Dimension::acceleration: return {1, -2, 0, 0};
  }
  return {};
}
// Exact comparison with a shorthand (the declared exponents, not the reduced dimension).
constexpr bool operator==(const Dimensions& a, Dimension d) { return a == dimensions_of(d); }

inline const char* to_string(ParamType t) {
  switch (t) {
    case ParamType::real: return "real";
    case ParamType::integer: return "integer";
    case ParamType::boolean: return "boolean";
    case ParamType::string: return "string";
    case ParamType::choice: return "choice";
  }
  return "?";
}

// The powers of d written with the four base names (length, time, temperature, mass order):
// "length^2 time^-3" with {"length", "time", "temperature", "mass"}; "" when dimensionless.
inline std::string powers_text(const Dimensions& d, const char* const (&base)[4]) {
  std::string s;
  const int exponents[4] = {d.length, d.time, d.temperature, d.mass};
  for (int i = 0; i < 4; ++i) {
    if (exponents[i] == 0) continue;
    if (!s.empty()) s += " ";
    s += base[i];
    if (exponents[i] != 1) s += "^" + std::to_string(exponents[i]);
  }
  return s;
}

// "velocity", or the powers: "length^2 time^-3", "1" when dimensionless.
inline std::string to_string(const Dimensions& d) {
  static constexpr struct { Dimension shorthand; const char* name; } named[] = {
      {Dimension::length, "length"},           {Dimension::time, "time"},
      {Dimension::inverse_time, "1/time"},     {Dimension::temperature, "temperature"},
      {Dimension::velocity, "velocity"},       {Dimension::acceleration, "acceleration"}};
  for (const auto& n : named)
    if (d == n.shorthand) return n.name;
  if (d.dimensionless()) return "1";
  return powers_text(d, {"length", "time", "temperature", "mass"});
}
inline std::string to_string(Dimension d) { return to_string(dimensions_of(d)); }

using ParamValue = std::variant<double, std::int64_t, bool, std::string>;

struct SourceLocation {
  std::string file;
  int line = 0;    // 1-based; 0 = unknown
  int column = 0;  // 1-based; 0 = unknown
  std::string str() const {
    if (file.empty()) return "<command line>";
    if (line == 0) return file;
    return file + ":" + std::to_string(line) + ":" + std::to_string(column);
  }
};

// One parameter of a plugin, as declared in its schema. Built fluently:
//   ParamSpec::real("alpha", "coefficient of normal restitution").range(0, 1).default_value(0.9)
struct ParamSpec {
  std::string name;
  ParamType type = ParamType::real;
  std::string doc;
  Dimensions dimension;                // dimensionless unless .unit() is given
  std::optional<ParamValue> default_;  // none: the parameter is required
  std::optional<double> min, max;      // for real and integer
  bool min_inclusive = true, max_inclusive = true;
  std::vector<std::string> choices;    // for choice

  static ParamSpec real(std::string n, std::string d) { return make(std::move(n), ParamType::real, std::move(d)); }
  static ParamSpec integer(std::string n, std::string d) { return make(std::move(n), ParamType::integer, std::move(d)); }
  static ParamSpec boolean(std::string n, std::string d) { return make(std::move(n), ParamType::boolean, std::move(d)); }
  static ParamSpec string(std::string n, std::string d) { return make(std::move(n), ParamType::string, std::move(d)); }
  static ParamSpec choice(std::string n, std::vector<std::string> c, std::string d) {
    ParamSpec s = make(std::move(n), ParamType::choice, std::move(d));
    s.choices = std::move(c);
    return s;
  }
  ParamSpec&& range(double lo, double hi) && { min = lo; max = hi; return std::move(*this); }
  ParamSpec&& above(double lo) && { min = lo; min_inclusive = false; return std::move(*this); }
  ParamSpec&& at_least(double lo) && { min = lo; return std::move(*this); }
  ParamSpec&& below(double hi) && { max = hi; max_inclusive = false; return std::move(*this); }
  ParamSpec&& unit(Dimension d) && { dimension = dimensions_of(d); return std::move(*this); }
  // Any product of powers, e.g. a noise strength (velocity^2 / time): .unit({.length = 2, .time = -3})
  ParamSpec&& unit(Dimensions d) && { dimension = d; return std::move(*this); }
  ParamSpec&& default_value(double v) && { default_ = v; return std::move(*this); }
  ParamSpec&& default_value(int v) && { default_ = std::int64_t{v}; return std::move(*this); }
  ParamSpec&& default_value(std::int64_t v) && { default_ = v; return std::move(*this); }
  ParamSpec&& default_value(bool v) && { default_ = v; return std::move(*this); }
  ParamSpec&& default_value(const char* v) && { default_ = std::string(v); return std::move(*this); }
  ParamSpec&& default_value(std::string v) && { default_ = std::move(v); return std::move(*this); }

  // "[0, 1]", "(0, inf)", "one of: a, b" or "" when unrestricted.
  std::string range_text() const {
    if (type == ParamType::choice) {
      std::string s = "one of:";
      for (const auto& c : choices) s += " " + c;
      return s;
    }
    if (!min && !max) return "";
    auto num = [](double v) {
      std::string s = std::to_string(v);
      s.erase(s.find_last_not_of('0') + 1);
      if (!s.empty() && s.back() == '.') s.pop_back();
      return s;
    };
    return std::string(min && min_inclusive ? "[" : "(") + (min ? num(*min) : "-inf") + ", " +
           (max ? num(*max) : "inf") + (max && max_inclusive ? "]" : ")");
  }

 private:
  static ParamSpec make(std::string n, ParamType t, std::string d) {
    ParamSpec s;
    s.name = std::move(n);
    s.type = t;
    s.doc = std::move(d);
    return s;
  }
};

inline std::string value_text(const ParamValue& v) {
  if (auto d = std::get_if<double>(&v)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", *d);
    return buf;
  }
  if (auto i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  if (auto b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  return std::get<std::string>(v);
}

// Thrown by a plugin (factory or constructor) that refuses a parameter value the schema could not
// express (e.g. a relation between two parameters). The host adds the file:line of the value.
class GDSMC_API ParameterError : public std::runtime_error {
 public:
  ParameterError(std::string parameter, const std::string& message)
      : std::runtime_error(message), parameter_(std::move(parameter)) {}
  const std::string& parameter() const { return parameter_; }

 private:
  std::string parameter_;
};

// Validated parameter values, in reduced units, as a plugin's factory receives them. Every
// declared parameter is present (given or defaulted).
class Params {
 public:
  struct Entry {
    ParamValue value;
    SourceLocation where;
    bool defaulted = false;
  };

  void set(const std::string& name, ParamValue v, SourceLocation where = {}, bool defaulted = false) {
    values_[name] = Entry{std::move(v), std::move(where), defaulted};
  }
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  const Entry& entry(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) throw ParameterError(name, "parameter '" + name + "' is not in the plugin's schema");
    return it->second;
  }
  double real(const std::string& name) const {
    const auto& v = entry(name).value;
    if (auto i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
    return get<double>(name, v);
  }
  std::int64_t integer(const std::string& name) const { return get<std::int64_t>(name, entry(name).value); }
  bool boolean(const std::string& name) const { return get<bool>(name, entry(name).value); }
  const std::string& string(const std::string& name) const { return get<std::string>(name, entry(name).value); }
  const std::map<std::string, Entry>& entries() const { return values_; }

 private:
  template <class T>
  static const T& get(const std::string& name, const ParamValue& v) {
    if (auto p = std::get_if<T>(&v)) return *p;
    throw ParameterError(name, "parameter '" + name + "' was read with the wrong type");
  }
  std::map<std::string, Entry> values_;
};

}  // namespace gdsmc
