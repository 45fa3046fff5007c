#pragma once
// TRANSFER_CLONES compiles a function twice: for x86-64-v3 (AVX2 and FMA) and for the build's
// own target (plain x86-64 by default); the dynamic loader picks the copy the CPU can run,
// once at start-up. It marks the loops of the two transfers (ParticleToGrid.cpp,
// GridToParticle.cpp), most of the solver's time: their x86-64-v3 copy, with fused
// multiply-adds and three-operand instructions, takes about a fifth less time, and a
// generic build still runs on every x86-64 CPU. The per-particle work must be inlined into
// the marked loop (always_inline) to be compiled in both ways.
//
// Rounding: a fused multiply-add rounds once where a multiply and an add round twice, so the
// two copies differ in the last bits. Results stay bit-identical run to run and for any
// thread count on one machine, but one binary gives other bits on a CPU with and a CPU
// without AVX2/FMA, and where a crack tip's growth is on its threshold, another crack path.
#if defined(__x86_64__) && defined(__GNUC__)
#define TRANSFER_CLONES [[gnu::target_clones("arch=x86-64-v3", "default")]]
#else
#define TRANSFER_CLONES
#endif
