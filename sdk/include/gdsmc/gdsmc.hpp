// gdsmc SDK: the contract, the one header every plugin includes. The physics toolkit (moments,
// kinetic theory, reservoirs, wall laws, series statistics) is <gdsmc/physics.hpp>: header-only
// helpers compiled into the plugins that use them, outside the ABI fingerprint.
#pragma once
#include "gdsmc/collision.hpp"
#include "gdsmc/context.hpp"
#include "gdsmc/output.hpp"
#include "gdsmc/params.hpp"
#include "gdsmc/particles.hpp"
#include "gdsmc/plugin.hpp"
#include "gdsmc/random.hpp"
#include "gdsmc/state.hpp"
#include "gdsmc/vec3.hpp"
#include "gdsmc/version.hpp"
