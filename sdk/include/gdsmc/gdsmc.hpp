// gdsmc SDK: the one header a plugin includes.
#pragma once
#include "gdsmc/collision.hpp"
#include "gdsmc/context.hpp"
#include "gdsmc/kinetic_theory.hpp"
#include "gdsmc/moments.hpp"
#include "gdsmc/output.hpp"
#include "gdsmc/params.hpp"
#include "gdsmc/particles.hpp"
#include "gdsmc/plugin.hpp"
#include "gdsmc/random.hpp"
#include "gdsmc/series.hpp"
#include "gdsmc/vec3.hpp"
#include "gdsmc/version.hpp"
