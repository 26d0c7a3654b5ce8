// RT_HD marks code that runs on both backends: __host__ __device__ under nvcc, plain C++
// otherwise. Introduced in chapter 01; every per-pixel and per-ray function carries it.
#pragma once

#if defined(__CUDACC__)
#define RT_HD __host__ __device__
#define RT_DEVICE_CODE_POSSIBLE 1
#else
#define RT_HD
#define RT_DEVICE_CODE_POSSIBLE 0
#endif

// True while nvcc compiles the device side of a translation unit.
#if defined(__CUDA_ARCH__)
#define RT_ON_DEVICE 1
#else
#define RT_ON_DEVICE 0
#endif

// Unrolls the loop that follows on the device (where a loop over a small fixed count, once
// unrolled, keeps its arrays in registers); the host's compiler decides for itself.
#if defined(__CUDA_ARCH__)
#define RT_UNROLL _Pragma("unroll")
#else
#define RT_UNROLL
#endif

// Asks the host's compiler to inline a function at every call (nvcc's device side inlines on
// its own judgement). For the small functions of a traversal's innermost loop on the CPU, where
// a call passes the ray and node through memory (chapter 09's CPU traversal).
#if !defined(__CUDA_ARCH__) && defined(__GNUC__)
#define RT_INLINE_ON_CPU [[gnu::always_inline]]
#else
#define RT_INLINE_ON_CPU
#endif
