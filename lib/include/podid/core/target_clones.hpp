#pragma once
// Hot loops of podid's modules built for several x86-64 levels, where GCC
// can pick between them at load time (target_clones, an ifunc), so the
// portable build keeps the speed of a -march=native one on CPUs that have
// AVX2/FMA (x86-64-v3) or AVX-512 (x86-64-v4); elsewhere (another
// architecture, clang) each is built once, for the target the build asks for.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PODID_CLONES_V3 __attribute__((target_clones("arch=x86-64-v3", "default")))
#define PODID_CLONES_V4 \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define PODID_CLONES_V3
#define PODID_CLONES_V4
#endif
