#include "config/units.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <vector>
#include <stdexcept>

#include "config/pipeline.hpp"

namespace gdsmc::host {

namespace {

// A dimension reduced to the independent base (mass, length, time), exponents possibly halves
// (sqrt), and the factor of a unit in reduced units.
struct Quantity {
  double factor = 1;
  double M = 0, L = 0, t = 0;
  Quantity& operator*=(const Quantity& o) {
    factor *= o.factor;
    M += o.M;
    L += o.L;
    t += o.t;
    return *this;
  }
  Quantity pow(double e) const { return {std::pow(factor, e), M * e, L * e, t * e}; }
  bool same_dimension(const Quantity& o) const {
    return std::abs(M - o.M) < 1e-9 && std::abs(L - o.L) < 1e-9 && std::abs(t - o.t) < 1e-9;
  }
};

// The base dimension of declared exponents: temperature = energy = M L^2 t^-2 (k_B = 1).
Quantity base_of(const Dimensions& d) {
  return {1.0, static_cast<double>(d.mass + d.temperature), static_cast<double>(d.length + 2 * d.temperature),
          static_cast<double>(d.time - 2 * d.temperature)};
}

// Recursive descent over a unit expression.
class UnitParser {
 public:
  UnitParser(const std::string& text, const UnitScales& s) : text_(text), s_(s) {}
  Quantity parse() {
    Quantity q = product();
    skip();
    if (pos_ != text_.size()) fail("unexpected '" + text_.substr(pos_) + "'");
    return q;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw std::invalid_argument(why); }
  void skip() {
    while (pos_ < text_.size() && text_[pos_] == ' ') ++pos_;
  }
  bool peek(char c) {
    skip();
    return pos_ < text_.size() && text_[pos_] == c;
  }
  bool at_factor() {
    skip();
    if (pos_ >= text_.size()) return false;
    const char c = text_[pos_];
    return c == '(' || std::isalnum(static_cast<unsigned char>(c)) || c == '.';
  }
  // factor (('*' | '/' | juxtaposition) factor)*
  Quantity product() {
    Quantity q = power();
    while (true) {
      if (peek('*')) {
        ++pos_;
        q *= power();
      } else if (peek('/')) {
        ++pos_;
        q *= power().pow(-1);
      } else if (at_factor()) {
        q *= power();
      } else {
        return q;
      }
    }
  }
  // atom ('^' exponent)?
  Quantity power() {
    Quantity q = atom();
    if (peek('^')) {
      ++pos_;
      q = q.pow(exponent());
    }
    return q;
  }
  double exponent() {
    skip();
    if (peek('(')) {
      ++pos_;
      double num = signed_number();
      double den = 1;
      if (peek('/')) {
        ++pos_;
        den = signed_number();
      }
      if (!peek(')')) fail("expected ')' in an exponent");
      ++pos_;
      if (den == 0) fail("zero denominator in an exponent");
      return num / den;
    }
    return signed_number();
  }
  double signed_number() {
    skip();
    double sign = 1;
    if (pos_ < text_.size() && (text_[pos_] == '-' || text_[pos_] == '+')) sign = text_[pos_++] == '-' ? -1 : 1;
    return sign * number();
  }
  double number() {
    skip();
    const std::size_t start = pos_;
    while (pos_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '.')) ++pos_;
    if (start == pos_) fail("expected a number at '" + text_.substr(start) + "'");
    return std::stod(text_.substr(start, pos_ - start));
  }
  Quantity atom() {
    skip();
    if (pos_ >= text_.size()) fail("unit ends early");
    const char c = text_[pos_];
    if (c == '(') {
      ++pos_;
      Quantity q = product();
      if (!peek(')')) fail("expected ')'");
      ++pos_;
      return q;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return {number(), 0, 0, 0};
    const std::size_t start = pos_;
    while (pos_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) ++pos_;
    const std::string name = text_.substr(start, pos_ - start);
    if (name == "sqrt") {
      if (!peek('(')) fail("expected sqrt(...)");
      return atom().pow(0.5);
    }
    if (name == "lambda0") return {s_.lambda0, 0, 1, 0};
    if (name == "sigma") return {s_.sigma, 0, 1, 0};
    if (name == "tau0") return {s_.tau0, 0, 0, 1};
    if (name == "T0") return {s_.T0, 1, 2, -2};
    if (name == "m") return {1.0, 1, 0, 0};
    if (name == "Ly") {
      if (!(s_.Ly > 0)) fail("unit 'Ly' (the gap of a slab) needs system.domain: slab");
      return {s_.Ly, 0, 1, 0};
    }
    fail("unknown unit '" + name + "'");
  }

  const std::string& text_;
  const UnitScales& s_;
  std::size_t pos_ = 0;
};

std::string base_text(const Quantity& q) {
  std::string s;
  auto power = [&s](const char* base, double e) {
    if (std::abs(e) < 1e-9) return;
    if (!s.empty()) s += " ";
    s += base;
    if (std::abs(e - 1) > 1e-9) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "^%g", e);
      s += buf;
    }
  };
  power("mass", q.M);
  power("length", q.L);
  power("time", q.t);
  return s.empty() ? "1" : s;
}

}  // namespace

UnitScales unit_scales(const Pipeline& p) {
  return {p.mean_free_path0(), p.time_unit0(), p.temperature, p.sigma, p.geometry == Geometry::slab ? p.box_y : 0.0};
}

namespace {

// The unit of dimension d in thermal units on the length `length`: length^(L + t) sqrt(2T0/m)^-t
// T0^T m^M, written as to_reduced() reads it ("2T0/(m sigma)", "Ly/sqrt(2T0/m)").
std::string thermal_unit(const Dimensions& d, const std::string& length) {
  std::vector<std::string> num, den;
  auto put = [&](const std::string& base, int e) {
    if (e == 0) return;
    (e > 0 ? num : den).push_back(std::abs(e) == 1 ? base : base + "^" + std::to_string(std::abs(e)));
  };
  const int speed = -d.time;
  if (speed == 2 || speed == -2) {
    (speed > 0 ? num : den).push_back("2T0");
    (speed > 0 ? den : num).push_back("m");
  } else {
    put("sqrt(2T0/m)", speed);
  }
  put(length, d.length + d.time);
  put("T0", d.temperature);
  put("m", d.mass);
  auto words = [](const std::vector<std::string>& w) {
    std::string s;
    for (const auto& x : w) s += (s.empty() ? "" : " ") + x;
    return s;
  };
  std::string text = num.empty() ? "1" : words(num);
  if (!den.empty()) text += "/" + (den.size() > 1 ? "(" + words(den) + ")" : den[0]);
  return text;
}

}  // namespace

std::string common_units_text(double reduced, const Dimensions& d, const UnitScales& s) {
  std::vector<std::string> units = {reference_unit(d), "reduced", thermal_unit(d, "lambda0"), thermal_unit(d, "sigma")};
  if (s.Ly > 0) units.push_back(thermal_unit(d, "Ly"));
  std::string text, why;
  std::vector<std::string> written;
  for (const auto& u : units) {
    if (std::find(written.begin(), written.end(), u) != written.end()) continue;
    const std::optional<double> factor = to_reduced(1.0, u, d, s, why);
    if (!factor || !(*factor != 0)) continue;
    char value[32];
    std::snprintf(value, sizeof value, "%.4g", reduced / *factor);
    text += std::string(text.empty() ? "" : " = ") + value + " " + u;
    written.push_back(u);
  }
  return text;
}

std::string reference_unit(const Dimensions& d) {
  return d.dimensionless() ? "1" : powers_text(d, {"lambda0", "tau0", "T0", "m"});
}

std::optional<double> to_reduced(double value, const std::string& unit, const Dimensions& d, const UnitScales& s,
                                 std::string& why) {
  const Quantity want = base_of(d);
  auto refuse = [&](const std::string& problem) -> std::optional<double> {
    why = problem + "; valid units for " + to_string(d) + ": reduced, " + reference_unit(d) +
          ", or any product of powers of lambda0, sigma, tau0, T0, m with this dimension";
    return std::nullopt;
  };
  if (unit == "reduced") return value;
  if (unit.empty()) return refuse("empty unit");
  Quantity q;
  try {
    q = UnitParser(unit, s).parse();
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  if (!q.same_dimension(want))
    return refuse("unit '" + unit + "' is " + base_text(q) + ", not " + base_text(want) +
                  " (with k_B = 1 a temperature is an energy, mass length^2 time^-2)");
  return value * q.factor;
}

std::optional<double> to_reduced(double value, const std::string& unit, const Dimensions& d, double lambda0, double tau0,
                                 double T0, double sigma, std::string& why) {
  return to_reduced(value, unit, d, UnitScales{lambda0, tau0, T0, sigma}, why);
}

double reference_factor(const Dimensions& d, const UnitScales& s) {
  return std::pow(s.lambda0, d.length) * std::pow(s.tau0, d.time) * std::pow(s.T0, d.temperature);  // m = 1
}

double reference_factor(const Dimensions& d, const Pipeline& p) { return reference_factor(d, unit_scales(p)); }

}  // namespace gdsmc::host
