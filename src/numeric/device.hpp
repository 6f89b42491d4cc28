// The one source of the double tier's step for two processors: ROTLEAK_HD marks a function that the GPU engine
// runs too (compiled by nvcc as __host__ __device__, the same operations in the same order as on the CPU; see
// docs/model.md, "The GPU engine"). Elsewhere it expands to nothing.
#pragma once

#if defined(__CUDACC__)
#define ROTLEAK_HD __host__ __device__
#else
#define ROTLEAK_HD
#endif
