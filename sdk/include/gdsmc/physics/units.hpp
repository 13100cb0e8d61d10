// gdsmc SDK, physics toolkit: the units of outputs, one spelling each. A diagnostic passes these to
// OutputSink (series, profile, array, histogram, scalar) rather than writing its own text, so that
// a reader (h5py, `gdsmc plot`, a report script) meets one string per unit; the host's test
// checks every unit that the shipped pipelines write against this list (docs/output-format.md
// gives their meanings). An in-tree plugin that needs a unit missing here adds it here, once; an
// out-of-tree one may write its own text.
#pragma once
#include <string_view>

namespace gdsmc::units {

// The reference scales of the papers (000 Eq. 4.1): T0 the initial temperature, n0 the mean number
// density, lambda0 = 1/(sqrt(2) pi n0 sigma^2), tau0 = lambda0/sqrt(2 T0/m).
inline constexpr const char* dimensionless = "1";
inline constexpr const char* temperature = "T0";
inline constexpr const char* time = "tau0";
inline constexpr const char* rate = "1/tau0";
inline constexpr const char* length = "lambda0";
inline constexpr const char* speed = "sqrt(2T0/m)";                   // the initial thermal speed
inline constexpr const char* density = "n0";
inline constexpr const char* pressure = "n0 T0";                      // stresses, P_ij
inline constexpr const char* heat_flux = "n0 T0 sqrt(2T0/m)";         // q_i, energy flux
inline constexpr const char* wall_hit_rate = "1/(lambda0^2 tau0)";    // hits per area and time
inline constexpr const char* viscosity = "eta0(T)";                   // the dilute eta0 at the current T
// Paper 004's channel (Eq. 19): the width W, the wall temperature T_w and its thermal speed, the
// mean mass density rho_av and the pressure scale rho_av u_R^2 / 2.
inline constexpr const char* channel_width = "W";
inline constexpr const char* wall_temperature = "T_w";
inline constexpr const char* wall_temperature_gradient = "T_w/W";
inline constexpr const char* wall_power = "T_w/tau0";
inline constexpr const char* wall_speed = "sqrt(2T_w/m)";
inline constexpr const char* wall_speed_gradient = "sqrt(2T_w/m)/W";
inline constexpr const char* mass_density = "rho_av";
inline constexpr const char* mass_density_gradient = "rho_av/W";
inline constexpr const char* channel_pressure = "rho_av u_R^2/2";
// The host's own: a sweep's numeric axis in the units its values were written in, and a column of
// text (labels), which has none.
inline constexpr const char* as_swept = "as given in the sweep";
inline constexpr const char* text = "";

inline constexpr const char* all[] = {
    dimensionless, temperature, time, rate, length, speed, density, pressure, heat_flux, wall_hit_rate, viscosity,
    channel_width, wall_temperature, wall_temperature_gradient, wall_power, wall_speed, wall_speed_gradient,
    mass_density, mass_density_gradient, channel_pressure, as_swept, text};

// Whether `unit` is spelled as this vocabulary spells it.
constexpr bool is_output_unit(std::string_view unit) {
  for (const char* u : all)
    if (std::string_view(u) == unit) return true;
  return false;
}

}  // namespace gdsmc::units
