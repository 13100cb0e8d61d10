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

// The physical dimension of a real parameter. The host converts values given with a unit
// ({value: 4, unit: 1/tau0}) into reduced units (m = 1, k_B = 1, sigma, T0) once, at load time.
enum class Dimension { none, length, time, inverse_time, temperature, velocity, acceleration };

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

inline const char* to_string(Dimension d) {
  switch (d) {
    case Dimension::none: return "1";
    case Dimension::length: return "length (lambda0 | sigma | reduced)";
    case Dimension::time: return "time (tau0 | reduced)";
    case Dimension::inverse_time: return "1/time (1/tau0 | reduced)";
    case Dimension::temperature: return "temperature (T0 | reduced)";
    case Dimension::velocity: return "velocity (sqrt(2T0/m) | reduced)";
    case Dimension::acceleration: return "acceleration (2T0/(m lambda0) | reduced)";
  }
  return "?";
}

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
  Dimension dimension = Dimension::none;
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
  ParamSpec&& unit(Dimension d) && { dimension = d; return std::move(*this); }
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
