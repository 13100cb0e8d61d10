// Deliberately broken (conformance test): the white-noise thermostat of conformance_white_noise
// declaring half its true heating rate (3 N D / 2). `gdsmc conformance` must report
// forcing.expected_energy FAIL.
#define GDSMC_WHITE_NOISE_HALF_RATE
#include "../conformance_white_noise/conformance_white_noise.cpp"
