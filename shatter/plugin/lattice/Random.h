#pragma once
// The lattice's generator is the shared one (plugin/common/Random.h).
#include <shatter/plugin/common/Random.h>

namespace shatter::lattice {

using Random = shatter::Random;

} // namespace shatter::lattice
