#pragma once
// STRIDEMAP_VECTOR_CLONES (internal): a function the compiler vectorises gets
// a copy built for AVX2, four doubles a vector, chosen when the library loads
// where the CPU has it (as in core). For loops that compare, select and
// subtract without FMA: both copies give the same bits.
// STRIDEMAP_NO_AVX2_COPIES leaves the baseline copy alone.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_PREPROCESS_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define STRIDEMAP_PREPROCESS_CLONES
#endif
