#pragma once
// A grid node's momentum and mass as one vector of four doubles (x, y, mass, 0), so that a
// transfer adds a particle's share to a node, or reads a node's velocity, in one operation:
// one AVX instruction in the x86-64-v3 copy of the transfer loops, two SSE2 instructions in
// the generic copy (TargetClones.h). The transfers are most of the solver's time, and most of
// their time was these per-node updates done one double at a time.
#include "plugin/mpm/Grid.h"

namespace shatter::mpm {

// GCC's (and Clang's) vector extension, declared as the compilers' own __m256d: may_alias
// lets a Packed4 read and write the doubles of a Grid::Node. A scalar in an arithmetic
// operation with a Packed4 stands for four copies of itself (s * v). Packed4 values are
// never passed to or returned from functions, whose calling convention would differ
// between the two copies of the transfer loops.
typedef double Packed4 __attribute__((vector_size(32), aligned(32), may_alias));

static_assert(sizeof(Grid::Node) == sizeof(Packed4) && alignof(Grid::Node) == alignof(Packed4),
              "a grid node must be exactly one packed vector (x, y, mass, 0)");

inline Packed4& packed(Grid::Node& n) { return *reinterpret_cast<Packed4*>(&n); }
inline const Packed4& packed(const Grid::Node& n) { return *reinterpret_cast<const Packed4*>(&n); }

} // namespace shatter::mpm
